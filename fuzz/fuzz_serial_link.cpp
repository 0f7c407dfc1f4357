// The serial link's frame coder and decoder (lib/link: cobs.c, link.c;
// docs/protocol/serial.md) on arbitrary bytes.
//
// Invariants, each on the same input:
//  1. COBS: decode(encode(x)) == x for the input bytes; the encoding has no
//     zero and fits PV_COBS_MAX_ENCODED; a buffer one byte short is refused;
//     the input decoded as COBS, when valid, is shorter than the input.
//  2. Messages: the input read as a pitvol.Message payload, when it decodes,
//     encodes again (<= pitvol_Message_size), framed (<= 310 bytes on the
//     wire) and received by a fresh link gives the same seq and the same
//     message (its canonical encoding, byte for byte).
//  3. Chunking: the input as a received byte stream, fed whole, byte by byte
//     and in random chunks, gives the same frames (seq and message), the
//     same statistics and the same answers queued (each command is acked;
//     a repeat is answered again by the link); every byte is consumed; the
//     corrupt counters add up; the answers, written out and received by a
//     fresh link, are all good frames.
//  4. Resynchronisation: valid frames built from pieces of the input, with
//     pieces of noise between them, all arrive, in order, whatever the noise
//     (a frame starts with a zero: noise before it cannot swallow it).
#include <algorithm>
#include <cstring>
#include <vector>

#include <pb_decode.h>
#include <pb_encode.h>

#include "fuzz_support.h"
#include "pitvol/cobs.h"
#include "pitvol/link.h"

namespace {

using Bytes = std::vector<uint8_t>;

// The canonical encoding of a message (what decode(encode(x)) == x compares:
// nanopb structs hold padding and unused union bytes).
Bytes encode_payload(const pitvol_Message &m) {
  Bytes out(PV_LINK_MAX_PAYLOAD_BYTES);
  pb_ostream_t os = pb_ostream_from_buffer(out.data(), out.size());
  PV_FUZZ_CHECK(pb_encode(&os, pitvol_Message_fields, &m), "a decoded message does not encode: %s",
                PB_GET_ERROR(&os));
  out.resize(os.bytes_written);
  return out;
}

bool decode_payload(const uint8_t *p, size_t n, pitvol_Message *m) {
  *m = pitvol_Message_init_zero;
  pb_istream_t is = pb_istream_from_buffer(p, n);
  return pb_decode(&is, pitvol_Message_fields, m);
}

void check_cobs(const uint8_t *data, size_t size) {
  Bytes enc(PV_COBS_MAX_ENCODED(size));
  const size_t n = pv_cobs_encode(data, size, enc.data(), enc.size());
  PV_FUZZ_CHECK(n > 0 && n <= enc.size(), "encoded %zu of %zu bytes into %zu", n, size, enc.size());
  PV_FUZZ_CHECK(std::find(enc.begin(), enc.begin() + long(n), 0) == enc.begin() + long(n),
                "a zero in the COBS encoding");
  Bytes dec(size + 1);
  int ok = 0;
  const size_t m = pv_cobs_decode(enc.data(), n, dec.data(), dec.size(), &ok);
  PV_FUZZ_CHECK(ok && m == size && (size == 0 || std::memcmp(dec.data(), data, size) == 0),
                "decode(encode(x)) != x (%zu bytes, ok %d, %zu back)", size, ok, m);
  PV_FUZZ_CHECK(pv_cobs_encode(data, size, enc.data(), enc.size() - 1) == 0,
                "encoded into a buffer one byte short of the worst case");
  if (size > 0) {
    const size_t got = pv_cobs_decode(enc.data(), n, dec.data(), size - 1, &ok);
    PV_FUZZ_CHECK(!ok && got == 0, "decoded %zu bytes into %zu", size, size - 1);
  }
  // The input as an encoding.
  Bytes raw(size + 1);
  const size_t r = pv_cobs_decode(data, size, raw.data(), raw.size(), &ok);
  if (ok) PV_FUZZ_CHECK(r < size, "COBS decoded %zu bytes from %zu", r, size);
}

void check_message(const uint8_t *data, size_t size, uint32_t seq) {
  pitvol_Message m;
  if (!decode_payload(data, size, &m)) return;
  const Bytes e1 = encode_payload(m);
  uint8_t wire[PV_LINK_MAX_WIRE_BYTES + 16];
  const size_t n = pv_link_encode_frame(&m, seq, wire, sizeof wire);
  PV_FUZZ_CHECK(n > 0 && n <= PV_LINK_MAX_WIRE_BYTES, "frame of %zu bytes", n);
  PV_FUZZ_CHECK(pv_link_encode_frame(&m, seq, wire, n - 1) == 0, "framed into too small a buffer");
  static pv_link_t link;
  pv_link_init(&link, 0);
  pv_link_rx_t rx;
  int got = 0;
  const size_t used = pv_link_feed(&link, wire, n, &rx, &got);
  PV_FUZZ_CHECK(got && used == n, "own frame not received (got %d, %zu of %zu bytes)", got, used, n);
  PV_FUZZ_CHECK(rx.seq == seq, "seq %u sent, %u received", seq, rx.seq);
  PV_FUZZ_CHECK(rx.msg.which_body == m.which_body, "message kind changed");
  PV_FUZZ_CHECK(encode_payload(rx.msg) == e1, "decode(encode(message)) differs");
  PV_FUZZ_CHECK(link.stats.frames_received == 1 && link.stats.frames_corrupt == 0,
                "received %u, corrupt %u", link.stats.frames_received, link.stats.frames_corrupt);
}

struct Received {
  std::vector<uint32_t> seqs;
  std::vector<Bytes> payloads;
};

long collect(void *ctx, const uint8_t *p, size_t n) {
  auto *out = static_cast<Bytes *>(ctx);
  out->insert(out->end(), p, p + n);
  return long(n);
}

// Feeds a stream in chunks (mode 0 whole, 1 byte by byte, 2 drawn sizes),
// acking every command handed on and writing the answers out.
void feed(pv_link_t *link, const uint8_t *data, size_t size, int mode, uint64_t seed,
          Received *rec, Bytes *tx) {
  pv_link_init(link, 7);
  pv::fuzz::Draw draw{seed};
  size_t at = 0;
  while (at < size) {
    size_t chunk = size - at;
    if (mode == 1) chunk = 1;
    if (mode == 2) chunk = std::min(chunk, 1 + draw.below(draw.below(4) == 0 ? 8 : 600));
    size_t done = 0;
    while (done < chunk) {
      pv_link_rx_t rx;
      int got = 0;
      const size_t used = pv_link_feed(link, data + at + done, chunk - done, &rx, &got);
      PV_FUZZ_CHECK(used > 0 && used <= chunk - done, "feed consumed %zu of %zu", used, chunk - done);
      done += used;
      PV_FUZZ_CHECK(got || done == chunk, "returned early without a frame");
      if (!got) continue;
      rec->seqs.push_back(rx.seq);
      rec->payloads.push_back(encode_payload(rx.msg));
      if (pv_link_is_command(&rx.msg)) (void)pv_link_ack(link, rx.seq, 1, 2, 3);
      PV_FUZZ_CHECK(pv_link_tx_flush(link, collect, tx) == PV_LINK_OK, "flush failed");
    }
    at += chunk;
  }
  PV_FUZZ_CHECK(pv_link_tx_flush(link, collect, tx) == PV_LINK_OK, "flush failed");
  pv_link_rx_t rx;
  int got = 1;
  PV_FUZZ_CHECK(pv_link_feed(link, data, 0, &rx, &got) == 0 && !got, "an empty read gave a frame");
}

void check_chunking(const uint8_t *data, size_t size, uint64_t seed) {
  static pv_link_t links[3];
  Received rec[3];
  Bytes tx[3];
  for (int mode = 0; mode < 3; ++mode) feed(&links[mode], data, size, mode, seed, &rec[mode], &tx[mode]);
  const pv_link_stats_t &s = links[0].stats;
  PV_FUZZ_CHECK(s.frames_corrupt == s.corrupt_cobs + s.corrupt_length + s.corrupt_crc +
                                        s.corrupt_version + s.corrupt_payload,
                "corrupt counters do not add up");
  PV_FUZZ_CHECK(s.frames_received == rec[0].seqs.size() + s.commands_duplicate,
                "received %u, handed on %zu, repeats %u", s.frames_received, rec[0].seqs.size(),
                s.commands_duplicate);
  for (int mode = 1; mode < 3; ++mode) {
    PV_FUZZ_CHECK(rec[mode].seqs == rec[0].seqs && rec[mode].payloads == rec[0].payloads,
                  "frames differ under chunking mode %d", mode);
    PV_FUZZ_CHECK(std::memcmp(&links[mode].stats, &s, sizeof s) == 0,
                  "statistics differ under chunking mode %d", mode);
    PV_FUZZ_CHECK(tx[mode] == tx[0], "answers differ under chunking mode %d", mode);
  }
  // Our answers are good frames for the other side.
  static pv_link_t peer;
  Received back;
  Bytes none;
  feed(&peer, tx[0].data(), tx[0].size(), 0, seed, &back, &none);
  PV_FUZZ_CHECK(peer.stats.frames_corrupt == 0, "%u of our answers are corrupt",
                peer.stats.frames_corrupt);
  PV_FUZZ_CHECK(back.seqs.size() == links[0].stats.frames_sent,
                "%zu answers received of %u sent", back.seqs.size(), links[0].stats.frames_sent);
}

// Pieces: [noise length][noise][payload length][payload] ... A payload that
// decodes becomes a frame; one that does not is noise too.
void check_resync(const uint8_t *data, size_t size, uint64_t seed) {
  Bytes wire;
  Received expected;
  uint32_t seq = uint32_t(seed);
  size_t at = 0;
  while (at < size) {
    const size_t want_noise = data[at++];
    const size_t noise = std::min(want_noise, size - at);
    wire.insert(wire.end(), data + at, data + at + noise);
    at += noise;
    if (at >= size) break;
    const size_t want_len = data[at++];
    const size_t len = std::min(want_len, size - at);
    pitvol_Message m;
    if (decode_payload(data + at, len, &m)) {
      uint8_t frame[PV_LINK_MAX_WIRE_BYTES];
      const size_t n = pv_link_encode_frame(&m, seq, frame, sizeof frame);
      PV_FUZZ_CHECK(n > 0, "a decoded message does not frame");
      wire.insert(wire.end(), frame, frame + n);
      expected.seqs.push_back(seq++);
      expected.payloads.push_back(encode_payload(m));
    } else {
      wire.insert(wire.end(), data + at, data + at + len);
    }
    at += len;
  }
  static pv_link_t link;
  Received got;
  Bytes tx;
  feed(&link, wire.data(), wire.size(), 2, seed, &got, &tx);
  // Every expected frame, in order, among those received (noise may hold
  // a valid frame of its own; a forged command with an expected frame's seq
  // would be taken for a repeat: then only the count is checked).
  size_t k = 0;
  for (size_t i = 0; i < got.seqs.size() && k < expected.seqs.size(); ++i) {
    if (got.seqs[i] == expected.seqs[k] && got.payloads[i] == expected.payloads[k]) ++k;
  }
  PV_FUZZ_CHECK(k == expected.seqs.size() || link.stats.commands_duplicate > 0,
                "%zu of %zu frames arrived through the noise", k, expected.seqs.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  uint64_t seed = 0;
  std::memcpy(&seed, data, std::min(size, sizeof seed));
  check_cobs(data, size);
  check_message(data, size, uint32_t(seed >> 32));
  check_chunking(data, size, seed);
  check_resync(data, size, seed);
  return 0;
}
