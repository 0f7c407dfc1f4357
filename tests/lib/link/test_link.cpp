// Serial link: COBS against published vectors, the documented frame layout,
// round trips of every message, the bounded queue (lossy Status, reliable
// Result) and resynchronisation after line noise, checked against an
// independent split of the noisy byte stream.
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "pitvol/cobs.h"
#include "pitvol/crc32c.h"
#include "pitvol/link.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using Bytes = std::vector<uint8_t>;

Bytes cobs(const Bytes &in) {
  Bytes out(PV_COBS_MAX_ENCODED(in.size()));
  const size_t n = pv_cobs_encode(in.data(), in.size(), out.data(), out.size());
  out.resize(n);
  return out;
}

void cobs_matches_the_published_examples(void **) {
  // Examples from Cheshire & Baker and the Wikipedia COBS article.
  assert_true(cobs({0x00}) == Bytes({0x01, 0x01}));
  assert_true(cobs({0x00, 0x00}) == Bytes({0x01, 0x01, 0x01}));
  assert_true(cobs({0x00, 0x11, 0x00}) == Bytes({0x01, 0x02, 0x11, 0x01}));
  assert_true(cobs({0x11, 0x22, 0x00, 0x33}) == Bytes({0x03, 0x11, 0x22, 0x02, 0x33}));
  assert_true(cobs({0x11, 0x22, 0x33, 0x44}) == Bytes({0x05, 0x11, 0x22, 0x33, 0x44}));
  assert_true(cobs({0x11, 0x00, 0x00, 0x00}) == Bytes({0x02, 0x11, 0x01, 0x01, 0x01}));
  Bytes run254(254);  // 01 .. FE -> FF 01 .. FE
  for (int i = 0; i < 254; ++i) run254[size_t(i)] = uint8_t(i + 1);
  Bytes want{0xff};
  want.insert(want.end(), run254.begin(), run254.end());
  assert_true(cobs(run254) == want);
  Bytes run255 = run254;  // 01 .. FF -> FF 01 .. FE 02 FF
  run255.push_back(0xff);
  want.push_back(0x02);
  want.push_back(0xff);
  assert_true(cobs(run255) == want);
  Bytes zero_then_254{0x00};  // 00 01 .. FE -> 01 FF 01 .. FE
  zero_then_254.insert(zero_then_254.end(), run254.begin(), run254.end());
  Bytes want2{0x01, 0xff};
  want2.insert(want2.end(), run254.begin(), run254.end());
  assert_true(cobs(zero_then_254) == want2);
}

void cobs_round_trips_and_never_emits_a_zero(void **) {
  pv::test::Rng rng{7};
  for (int trial = 0; trial < 400; ++trial) {
    Bytes in(size_t(rng.next() % 800));
    const bool sparse = trial % 2;  // half the inputs mostly zeros
    for (auto &b : in) b = sparse && rng.next() % 3 ? 0 : uint8_t(rng.next());
    const Bytes enc = cobs(in);
    assert_true(enc.size() <= PV_COBS_MAX_ENCODED(in.size()));
    for (uint8_t b : enc) assert_int_not_equal(b, 0);
    Bytes dec(in.size() + 1);
    int ok = 0;
    const size_t n = pv_cobs_decode(enc.data(), enc.size(), dec.data(), dec.size(), &ok);
    assert_true(ok);
    dec.resize(n);
    assert_true(dec == in);
  }
  // Invalid: a code byte pointing past the end, a zero inside.
  int ok = 1;
  uint8_t out[8];
  const uint8_t past[] = {0x05, 0x11, 0x22};
  assert_int_equal(pv_cobs_decode(past, sizeof past, out, sizeof out, &ok), 0);
  assert_false(ok);
  const uint8_t zero[] = {0x03, 0x11, 0x00};
  assert_int_equal(pv_cobs_decode(zero, sizeof zero, out, sizeof out, &ok), 0);
  assert_false(ok);
}

pitvol_Message get_results(uint32_t from) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_get_results_tag;
  m.body.get_results.from_id = from;
  return m;
}

pitvol_Message result(uint32_t id) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_result_tag;
  pitvol_Result &r = m.body.result;
  r.id = id;
  r.time_unix_s = 1790000000ull + id;
  std::strcpy(r.method, "polar");
  r.volume_cm3 = 1500.25 + id;
  r.interval_cm3 = 12.5;
  r.depth_mm = 150.0;
  r.warnings = 0x41;
  r.has_density = true;
  r.density.flags = pitvol_DensityFlag_DENSITY_WET;
  r.density.mass_g = 3000.0;
  r.density.wet_kg_m3 = 1999.0;
  return m;
}

pitvol_Message status(uint64_t points) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_status_tag;
  m.body.status.state = pitvol_DeviceState_STATE_SCANNING;
  m.body.status.points = points;
  m.body.status.coverage_count = 16;
  for (int i = 0; i < 16; ++i) m.body.status.coverage[i] = float(i) / 16.0f;
  return m;
}

void frame_bytes_follow_the_documented_layout(void **) {
  uint8_t wire[PV_LINK_MAX_WIRE_BYTES];
  const pitvol_Message m = get_results(5);
  const size_t n = pv_link_encode_frame(&m, 0x01020304u, wire, sizeof wire);
  assert_true(n > 2);
  assert_int_equal(wire[0], 0);
  assert_int_equal(wire[n - 1], 0);
  uint8_t raw[64];
  int ok = 0;
  const size_t r = pv_cobs_decode(wire + 1, n - 2, raw, sizeof raw, &ok);
  assert_true(ok);
  // version, seq LE, protobuf: field 21 (GetResults), length 2, field 1 = 5.
  const uint8_t body[] = {1, 0x04, 0x03, 0x02, 0x01, 0xaa, 0x01, 0x02, 0x08, 0x05};
  assert_int_equal(r, sizeof body + 4);
  assert_memory_equal(raw, body, sizeof body);
  const uint32_t crc = pv_crc32c(0, body, sizeof body);
  assert_int_equal(raw[10] | raw[11] << 8 | raw[12] << 16 | uint32_t(raw[13]) << 24, crc);
}

// Sends through a link into a byte vector.
long write_all(void *ctx, const uint8_t *d, size_t n) {
  auto *v = static_cast<Bytes *>(ctx);
  v->insert(v->end(), d, d + n);
  return long(n);
}

std::vector<pv_link_rx_t> feed_all(pv_link_t *rx, const Bytes &bytes, size_t chunk) {
  std::vector<pv_link_rx_t> got;
  for (size_t at = 0; at < bytes.size();) {
    const size_t len = std::min(chunk, bytes.size() - at);
    size_t used = 0;
    while (used < len) {
      pv_link_rx_t m;
      int g = 0;
      used += pv_link_feed(rx, bytes.data() + at + used, len - used, &m, &g);
      if (g) got.push_back(m);
    }
    at += len;
  }
  return got;
}

void every_message_survives_a_round_trip_in_any_chunking(void **) {
  std::vector<pitvol_Message> msgs;
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_hello_tag;
  m.body.hello.protocol_version = PV_LINK_PROTOCOL_VERSION;
  std::strcpy(m.body.hello.firmware_version, "0.1.0");
  std::strcpy(m.body.hello.device_id, "PV-000042");
  m.body.hello.max_frame_bytes = PV_LINK_MAX_WIRE_BYTES;
  msgs.push_back(m);
  msgs.push_back(status(123456));
  msgs.push_back(result(7));
  m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_error_tag;
  m.body.error.code = 8;
  std::memset(m.body.error.message, 'x', sizeof m.body.error.message - 1);  // longest
  msgs.push_back(m);
  m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_nack_tag;
  m.body.nack.code = pitvol_NackCode_NACK_OUT_OF_RANGE;
  std::strcpy(m.body.nack.reason, "mass must be > 0 g");
  msgs.push_back(m);
  for (int tag : {pitvol_Message_get_hello_tag, pitvol_Message_start_scan_tag,
                  pitvol_Message_stop_scan_tag}) {
    m = pitvol_Message_init_zero;
    m.which_body = pb_size_t(tag);
    msgs.push_back(m);
  }
  m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_set_mass_tag;
  m.body.set_mass.mass_g = 2871.5;
  msgs.push_back(m);
  m.which_body = pitvol_Message_set_moisture_tag;
  m.body.set_moisture.moisture_percent = 12.25;
  msgs.push_back(m);
  msgs.push_back(get_results(3));

  for (size_t chunk : {size_t(1), size_t(3), size_t(64), size_t(100000)}) {
    static pv_link_t tx, rx;
    pv_link_init(&tx, 0xfffffffeu);  // the sequence wraps inside the test
    pv_link_init(&rx, 0);
    Bytes wire;
    for (const auto &msg : msgs) {
      assert_int_equal(pv_link_send(&tx, &msg, PV_LINK_RELIABLE, nullptr), PV_LINK_OK);
      assert_int_equal(pv_link_tx_flush(&tx, write_all, &wire), PV_LINK_OK);
      // Every frame fits the advertised maximum.
    }
    assert_int_equal(tx.stats.frames_sent, msgs.size());
    const auto got = feed_all(&rx, wire, chunk);
    assert_int_equal(got.size(), msgs.size());
    for (size_t i = 0; i < msgs.size(); ++i) {
      assert_int_equal(got[i].seq, uint32_t(0xfffffffeu + i));
      // Re-encoding the decoded message gives the same bytes.
      uint8_t a[PV_LINK_MAX_WIRE_BYTES], b[PV_LINK_MAX_WIRE_BYTES];
      const size_t na = pv_link_encode_frame(&msgs[i], 1, a, sizeof a);
      const size_t nb = pv_link_encode_frame(&got[i].msg, 1, b, sizeof b);
      assert_int_equal(na, nb);
      assert_memory_equal(a, b, na);
      assert_true(na <= PV_LINK_MAX_WIRE_BYTES);
    }
    assert_int_equal(rx.stats.frames_corrupt, 0);
    assert_int_equal(rx.stats.frames_missed, 0);
    assert_int_equal(rx.stats.commands_duplicate, 0);
  }
}

void a_flipped_bit_costs_one_frame_and_the_reader_resyncs(void **) {
  static pv_link_t tx, rx;
  pv_link_init(&tx, 10);
  pv_link_init(&rx, 0);
  Bytes wire{0x13, 0x37, 0x55};  // garbage before the first frame
  for (uint32_t id = 1; id <= 3; ++id) {
    const pitvol_Message m = result(id);
    assert_int_equal(pv_link_send(&tx, &m, PV_LINK_RELIABLE, nullptr), PV_LINK_OK);
    assert_int_equal(pv_link_tx_flush(&tx, write_all, &wire), PV_LINK_OK);
  }
  // Flip one bit in the middle of the second frame (never making a zero).
  size_t second = 0, zeros = 0;
  for (size_t i = 3; i < wire.size(); ++i)
    if (wire[i] == 0 && ++zeros == 2) { second = i + 1; break; }
  size_t at = second + 40;
  while ((wire[at] ^ 0x10) == 0) ++at;
  wire[at] ^= 0x10;
  const auto got = feed_all(&rx, wire, 5);
  assert_int_equal(got.size(), 2);
  assert_int_equal(got[0].msg.body.result.id, 1);
  assert_int_equal(got[1].msg.body.result.id, 3);
  // The garbage prefix and the flipped frame.
  assert_int_equal(rx.stats.frames_corrupt, 2);
  assert_int_equal(rx.stats.frames_missed, 1);
}

// A host that restarts begins at a new random seq: that jump is a new peer,
// not four billion lost frames; a gap of a few frames is still counted.
void a_restarted_host_is_a_new_peer_not_lost_frames(void **) {
  static pv_link_t tx, rx;
  pv_link_init(&rx, 0);
  Bytes wire;
  const uint32_t firsts[] = {1000, 1004, 1004 + 3000000, 1004 + 3000000 + PV_LINK_MAX_SEQ_GAP + 1};
  for (uint32_t first : firsts) {
    pv_link_init(&tx, first);  // one frame from each "host"
    const pitvol_Message m = status(first);
    assert_int_equal(pv_link_send(&tx, &m, PV_LINK_RELIABLE, nullptr), PV_LINK_OK);
    assert_int_equal(pv_link_tx_flush(&tx, write_all, &wire), PV_LINK_OK);
  }
  const auto got = feed_all(&rx, wire, 7);
  assert_int_equal(got.size(), 4);
  assert_int_equal(rx.stats.frames_missed, 3);   // 1000 -> 1004
  assert_int_equal(rx.stats.peer_restarts, 2);   // the two large jumps
}

// 1 % of bytes flipped, dropped or preceded by an inserted byte. Truth
// without the decoder: split the noisy stream at zeros; a piece equal to a
// sent frame's COBS body is a good frame, any other piece a corrupt one.
void line_noise_every_corrupt_frame_is_counted(void **) {
  static pv_link_t tx, rx;
  pv_link_init(&tx, 0);
  pv_link_init(&rx, 0);
  pv::test::Rng rng{2026};
  Bytes clean;
  std::set<Bytes> bodies;
  for (uint32_t i = 0; i < 2000; ++i) {
    const pitvol_Message m = i % 3 ? status(i) : result(i);
    assert_int_equal(pv_link_send(&tx, &m, PV_LINK_RELIABLE, nullptr), PV_LINK_OK);
    const size_t from = clean.size();
    assert_int_equal(pv_link_tx_flush(&tx, write_all, &clean), PV_LINK_OK);
    bodies.insert(Bytes(clean.begin() + long(from) + 1, clean.end() - 1));
  }
  Bytes noisy;
  for (uint8_t b : clean) {
    if (rng.next() % 100 == 0) {
      switch (rng.next() % 3) {
        case 0: noisy.push_back(uint8_t(b ^ (1u << (rng.next() % 8)))); break;
        case 1: break;  // dropped
        default: noisy.push_back(uint8_t(rng.next())); noisy.push_back(b); break;
      }
    } else {
      noisy.push_back(b);
    }
  }
  size_t good = 0, corrupt = 0;
  Bytes piece;
  for (uint8_t b : noisy) {
    if (b != 0) { piece.push_back(b); continue; }
    if (!piece.empty()) (bodies.count(piece) ? good : corrupt)++;
    piece.clear();
  }
  const auto got = feed_all(&rx, noisy, 97);
  assert_int_equal(got.size(), good);
  assert_int_equal(rx.stats.frames_corrupt, corrupt);
  assert_true(corrupt > 100);  // the noise did hit
  assert_true(good > 300);   // and frames still got through
  print_message("noise: %zu good, %zu corrupt frames of 2000\n", good, corrupt);
  // What arrived is in order and intact: ids increase, results decode right.
  for (size_t i = 1; i < got.size(); ++i) assert_true(got[i].seq > got[i - 1].seq);
  for (const auto &g : got)
    if (g.msg.which_body == pitvol_Message_result_tag)
      assert_true(g.msg.body.result.volume_cm3 == 1500.25 + g.msg.body.result.id);
  assert_int_equal(rx.stats.frames_missed, got.back().seq - got.front().seq + 1 - got.size());
}

void status_is_replaced_and_dropped_results_never(void **) {
  static pv_link_t l;
  pv_link_init(&l, 0);
  // Three statuses in a row: only the newest waits.
  for (uint64_t p = 1; p <= 3; ++p) {
    const pitvol_Message s = status(p);
    const pv_link_status_t st = pv_link_send(&l, &s, PV_LINK_LOSSY, nullptr);
    assert_true(st == PV_LINK_OK || st == PV_LINK_DROPPED);  // lossy: a full queue drops it
  }
  assert_int_equal(l.tx_count, 1);
  assert_int_equal(l.stats.lossy_dropped, 2);
  // Results fill the queue and evict the status; the ninth is refused.
  uint32_t accepted = 0;
  for (uint32_t id = 1; id <= PV_LINK_TX_SLOTS + 1; ++id) {
    const pitvol_Message r = result(id);
    const pv_link_status_t st = pv_link_send(&l, &r, PV_LINK_RELIABLE, nullptr);
    if (st == PV_LINK_OK) accepted++;
    else assert_int_equal(st, PV_LINK_QUEUE_FULL);
  }
  assert_int_equal(accepted, PV_LINK_TX_SLOTS);
  assert_int_equal(pv_link_tx_room(&l), 0);
  const pitvol_Message s = status(9);
  assert_int_equal(pv_link_send(&l, &s, PV_LINK_LOSSY, nullptr), PV_LINK_DROPPED);
  // What goes out: exactly results 1..8, in order.
  static pv_link_t rx;
  pv_link_init(&rx, 0);
  Bytes wire;
  assert_int_equal(pv_link_tx_flush(&l, write_all, &wire), PV_LINK_OK);
  const auto got = feed_all(&rx, wire, wire.size());
  assert_int_equal(got.size(), PV_LINK_TX_SLOTS);
  for (uint32_t i = 0; i < PV_LINK_TX_SLOTS; ++i) {
    assert_int_equal(got[i].msg.which_body, pitvol_Message_result_tag);
    assert_int_equal(got[i].msg.body.result.id, i + 1);
  }
}

// A host that reads a few bytes now and then: the board never waits, every
// result it queued arrives once, in order, and statuses are shed instead.
struct Trickle {
  pv::test::Rng rng{99};
  Bytes out;
};
long write_some(void *ctx, const uint8_t *d, size_t n) {
  auto *t = static_cast<Trickle *>(ctx);
  const size_t take = std::min<size_t>(n, t->rng.next() % 40);
  t->out.insert(t->out.end(), d, d + take);
  return long(take);
}

void a_slow_host_loses_statuses_but_no_result(void **) {
  static pv_link_t l, rx;
  pv_link_init(&l, 0);
  pv_link_init(&rx, 0);
  Trickle host;
  uint32_t next_id = 1;
  for (int tick = 0; tick < 5000; ++tick) {
    const pitvol_Message s = status(uint64_t(tick));
    const pv_link_status_t st = pv_link_send(&l, &s, PV_LINK_LOSSY, nullptr);
    assert_true(st == PV_LINK_OK || st == PV_LINK_DROPPED);  // lossy: a full queue drops it
    if (tick % 3 == 0 && next_id <= 500) {  // a result is due; retry while full
      const pitvol_Message r = result(next_id);
      if (pv_link_send(&l, &r, PV_LINK_RELIABLE, nullptr) == PV_LINK_OK) next_id++;
    }
    if (tick % 2) assert_int_equal(pv_link_tx_flush(&l, write_some, &host), PV_LINK_OK);
  }
  while (pv_link_tx_pending(&l)) {
    assert_int_equal(pv_link_tx_flush(&l, write_some, &host), PV_LINK_OK);
  }
  assert_int_equal(next_id, 501);
  const auto got = feed_all(&rx, host.out, 4096);
  uint32_t want = 1;
  size_t statuses = 0;
  for (const auto &g : got) {
    if (g.msg.which_body == pitvol_Message_result_tag) assert_int_equal(g.msg.body.result.id, want++);
    else statuses++;
  }
  assert_int_equal(want, 501);
  assert_int_equal(rx.stats.frames_corrupt, 0);  // partial writes never tear a frame
  assert_true(l.stats.lossy_dropped > 0);
  assert_int_equal(statuses + l.stats.lossy_dropped, 5000);
}

void a_repeated_command_is_answered_again_not_handed_on(void **) {
  static pv_link_t host, board;
  pv_link_init(&host, 41);
  pv_link_init(&board, 0);
  const pitvol_Message cmd = get_results(1);
  Bytes wire;
  uint32_t seq = 0;
  assert_int_equal(pv_link_send(&host, &cmd, PV_LINK_RELIABLE, &seq), PV_LINK_OK);
  assert_int_equal(seq, 41);
  assert_int_equal(pv_link_tx_flush(&host, write_all, &wire), PV_LINK_OK);
  // The first copy reaches the board, which answers.
  auto got = feed_all(&board, wire, wire.size());
  assert_int_equal(got.size(), 1);
  assert_int_equal(got[0].seq, 41);
  // A repeat before the answer exists is ignored (the answer will come).
  got = feed_all(&board, wire, wire.size());
  assert_int_equal(got.size(), 0);
  assert_int_equal(pv_link_ack(&board, 41, 1, 9, 9), PV_LINK_OK);
  // The host missed the Ack and sends the command again, same seq: the
  // very same bytes.
  Bytes again;
  assert_int_equal(pv_link_send_again(&host, &cmd, 41), PV_LINK_OK);
  assert_int_equal(pv_link_tx_flush(&host, write_all, &again), PV_LINK_OK);
  assert_true(again == wire);
  got = feed_all(&board, again, again.size());
  assert_int_equal(got.size(), 0);
  assert_int_equal(board.stats.commands_duplicate, 2);
  Bytes back;
  assert_int_equal(pv_link_tx_flush(&board, write_all, &back), PV_LINK_OK);
  const auto acks = feed_all(&host, back, back.size());
  assert_int_equal(acks.size(), 2);
  for (const auto &a : acks) {
    assert_int_equal(a.msg.which_body, pitvol_Message_ack_tag);
    assert_int_equal(a.msg.body.ack.command_seq, 41);
    assert_int_equal(a.msg.body.ack.last_id, 9);
  }
  // The next command (new seq) goes through.
  Bytes wire2;
  assert_int_equal(pv_link_send(&host, &cmd, PV_LINK_RELIABLE, &seq), PV_LINK_OK);
  assert_int_equal(pv_link_tx_flush(&host, write_all, &wire2), PV_LINK_OK);
  got = feed_all(&board, wire2, wire2.size());
  assert_int_equal(got.size(), 1);
  assert_int_equal(got[0].seq, 42);
}

void oversized_and_unknown_input_is_rejected_and_counted(void **) {
  static pv_link_t rx;
  pv_link_init(&rx, 0);
  Bytes junk(PV_LINK_MAX_WIRE_BYTES * 3, 0x5a);  // no delimiter for too long
  junk.push_back(0);
  uint8_t bad_version[PV_LINK_MAX_WIRE_BYTES];
  const pitvol_Message m = get_results(1);
  // Frame version 2: rebuild one by hand.
  uint8_t raw[16] = {2, 0, 0, 0, 0, 0xaa, 0x01, 0x02, 0x08, 0x01};
  const uint32_t crc = pv_crc32c(0, raw, 10);
  for (int i = 0; i < 4; ++i) raw[10 + i] = uint8_t(crc >> (8 * i));
  bad_version[0] = 0;
  const size_t n = pv_cobs_encode(raw, 14, bad_version + 1, sizeof bad_version - 2);
  bad_version[n + 1] = 0;
  junk.insert(junk.end(), bad_version, bad_version + n + 2);
  uint8_t short_frame[] = {0, 0x02, 0x01, 0};  // one byte: too short
  junk.insert(junk.end(), short_frame, short_frame + sizeof short_frame);
  uint8_t good[PV_LINK_MAX_WIRE_BYTES];
  const size_t g = pv_link_encode_frame(&m, 5, good, sizeof good);
  junk.insert(junk.end(), good, good + g);
  const auto got = feed_all(&rx, junk, 50);
  assert_int_equal(got.size(), 1);
  assert_int_equal(got[0].msg.body.get_results.from_id, 1);
  assert_int_equal(rx.stats.corrupt_length, 2);
  assert_int_equal(rx.stats.corrupt_version, 1);
  assert_int_equal(rx.stats.frames_corrupt, 3);
}

// Pure garbage in any chunking: nothing is taken for a frame, nothing
// read out of bounds (ASan in the debug preset), every piece counted.
void random_bytes_never_make_a_frame(void **) {
  static pv_link_t rx;
  pv_link_init(&rx, 0);
  pv::test::Rng rng{31337};
  Bytes junk(200000);
  size_t zeros = 0;
  for (auto &b : junk) {
    b = uint8_t(rng.next());
    if (rng.next() % 50 == 0) b = 0;  // delimiters now and then
    zeros += b == 0;
  }
  const auto got = feed_all(&rx, junk, 1 + size_t(rng.next() % 700));
  assert_int_equal(got.size(), 0);
  assert_true(rx.stats.frames_corrupt > zeros / 2);
  assert_true(rx.stats.frames_corrupt <= zeros);
}

// An answer refused by a full queue is still kept: the repeat of the
// command gets it once there is room.
void an_answer_refused_by_a_full_queue_still_answers_the_repeat(void **) {
  static pv_link_t board;
  pv_link_init(&board, 0);
  uint8_t cmd[PV_LINK_MAX_WIRE_BYTES];
  const pitvol_Message gr = get_results(1);
  const size_t n = pv_link_encode_frame(&gr, 77, cmd, sizeof cmd);
  Bytes wire(cmd, cmd + n);
  assert_int_equal(feed_all(&board, wire, wire.size()).size(), 1);
  for (uint32_t id = 1; id <= PV_LINK_TX_SLOTS; ++id) {
    const pitvol_Message r = result(id);
    assert_int_equal(pv_link_send(&board, &r, PV_LINK_RELIABLE, nullptr), PV_LINK_OK);
  }
  assert_int_equal(pv_link_ack(&board, 77, 1, 8, 8), PV_LINK_QUEUE_FULL);
  Bytes out;
  // The host reads; room again.
  assert_int_equal(pv_link_tx_flush(&board, write_all, &out), PV_LINK_OK);
  assert_int_equal(feed_all(&board, wire, wire.size()).size(), 0);  // the repeat
  out.clear();
  assert_int_equal(pv_link_tx_flush(&board, write_all, &out), PV_LINK_OK);
  static pv_link_t host;
  pv_link_init(&host, 0);
  const auto back = feed_all(&host, out, out.size());
  assert_int_equal(back.size(), 1);
  assert_int_equal(back[0].msg.which_body, pitvol_Message_ack_tag);
  assert_int_equal(back[0].msg.body.ack.command_seq, 77);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(cobs_matches_the_published_examples),
      cmocka_unit_test(cobs_round_trips_and_never_emits_a_zero),
      cmocka_unit_test(frame_bytes_follow_the_documented_layout),
      cmocka_unit_test(every_message_survives_a_round_trip_in_any_chunking),
      cmocka_unit_test(a_flipped_bit_costs_one_frame_and_the_reader_resyncs),
      cmocka_unit_test(line_noise_every_corrupt_frame_is_counted),
      cmocka_unit_test(a_restarted_host_is_a_new_peer_not_lost_frames),
      cmocka_unit_test(status_is_replaced_and_dropped_results_never),
      cmocka_unit_test(a_slow_host_loses_statuses_but_no_result),
      cmocka_unit_test(a_repeated_command_is_answered_again_not_handed_on),
      cmocka_unit_test(oversized_and_unknown_input_is_rejected_and_counted),
      cmocka_unit_test(random_bytes_never_make_a_frame),
      cmocka_unit_test(an_answer_refused_by_a_full_queue_still_answers_the_repeat),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
