/* pitvol serial link: framing, bounded outgoing queue, resynchronising
 * decoder, repeated-command answers (see pitvol/link.h). */
#include "pitvol/link.h"

#include <string.h>

#include <pb_decode.h>
#include <pb_encode.h>

#include "pitvol/cobs.h"
#include "pitvol/crc32c.h"
#include "pitvol/le_bytes.h"

_Static_assert(PV_LINK_DROPPED > PV_STATUS_BASE_LINK &&
                   PV_LINK_RECORD_OUT_OF_RANGE < PV_STATUS_BASE_LINK + PV_STATUS_RANGE,
               "pv_link_status_t in its range (pitvol/status_codes.h)");

_Static_assert(PV_LINK_MAX_WIRE_BYTES < 0xffffu, "slot length is 16 bits");

const char *pv_link_status_name(pv_link_status_t status) {
  switch (status) {
    case PV_LINK_OK: return "PV_LINK_OK";
    case PV_LINK_DROPPED: return "PV_LINK_DROPPED";
    case PV_LINK_QUEUE_FULL: return "PV_LINK_QUEUE_FULL";
    case PV_LINK_ENCODE_FAILED: return "PV_LINK_ENCODE_FAILED";
    case PV_LINK_INVALID_ARGUMENT: return "PV_LINK_INVALID_ARGUMENT";
    case PV_LINK_WRITE_FAILED: return "PV_LINK_WRITE_FAILED";
    case PV_LINK_RECORD_TEXT: return "PV_LINK_RECORD_TEXT";
    case PV_LINK_RECORD_OUT_OF_RANGE: return "PV_LINK_RECORD_OUT_OF_RANGE";
  }
  return "PV_LINK_UNKNOWN";
}

const char *pv_link_status_message(pv_link_status_t status) {
  switch (status) {
    case PV_LINK_OK: return "sent";
    case PV_LINK_DROPPED:
      return "a status message was dropped because the serial link is slower than the "
             "board; results are not affected";
    case PV_LINK_QUEUE_FULL:
      return "the serial send queue is full of results and answers; they stay in the "
             "log, send again once the host reads (check the cable and the host program)";
    case PV_LINK_ENCODE_FAILED:
      return "a message did not fit the protocol's size limits; this is a bug, please "
             "report it";
    case PV_LINK_INVALID_ARGUMENT: return "a NULL pointer was passed to the link; a caller bug";
    case PV_LINK_WRITE_FAILED:
      return "writing to the serial port failed; check the cable and the port";
    case PV_LINK_RECORD_TEXT:
      return "a test record's text is too long or holds a control character; the record is "
             "unchanged, send it again in printable text";
    case PV_LINK_RECORD_OUT_OF_RANGE:
      return "a test record's number lies outside its allowed range; the record is unchanged";
  }
  return "unknown link status";
}

size_t pv_link_encode_frame(const pitvol_Message *msg, uint32_t seq, uint8_t *out, size_t cap) {
  uint8_t raw[PV_LINK_MAX_RAW_BYTES];
  if (!msg || !out || cap < 2) return 0;
  raw[0] = (uint8_t)PV_LINK_FRAME_VERSION;
  pv_put_le32(raw + 1, seq);
  pb_ostream_t os = pb_ostream_from_buffer(raw + PV_LINK_HEADER_BYTES, PV_LINK_MAX_PAYLOAD_BYTES);
  if (!pb_encode(&os, pitvol_Message_fields, msg)) return 0;
  const size_t body = PV_LINK_HEADER_BYTES + os.bytes_written;
  pv_put_le32(raw + body, pv_crc32c(0, raw, body));
  /* A leading zero too: whatever noise preceded this frame ends there. */
  out[0] = 0;
  const size_t n = pv_cobs_encode(raw, body + PV_LINK_CRC_BYTES, out + 1, cap - 2);
  if (n == 0) return 0;
  out[1 + n] = 0;
  return n + 2;
}

void pv_link_init(pv_link_t *link, uint32_t first_seq) {
  if (!link) return;
  memset(link, 0, sizeof *link);
  link->tx_seq = first_seq;
}

static pv_link_tx_slot_t *slot_at(pv_link_t *link, uint32_t i) {
  return &link->tx[(link->tx_head + i) % PV_LINK_TX_SLOTS];
}

/* Slot i may still be taken out: not the one being written. */
static int removable(const pv_link_t *link, uint32_t i) {
  return !(i == 0 && link->tx_written > 0);
}

static void remove_slot(pv_link_t *link, uint32_t i) {
  for (uint32_t k = i; k + 1 < link->tx_count; ++k) *slot_at(link, k) = *slot_at(link, k + 1);
  link->tx_count--;
  if (i == 0) link->tx_written = 0;
  link->stats.lossy_dropped++;
}

uint32_t pv_link_tx_room(const pv_link_t *link) {
  if (!link) return 0;
  uint32_t room = PV_LINK_TX_SLOTS - link->tx_count;
  for (uint32_t i = 0; i < link->tx_count; ++i)
    if (link->tx[(link->tx_head + i) % PV_LINK_TX_SLOTS].lossy && removable(link, i)) room++;
  return room;
}

static pv_link_status_t enqueue(pv_link_t *link, const pitvol_Message *msg, pv_link_class_t cls,
                                uint32_t seq, int fresh_seq) {
  uint8_t wire[PV_LINK_MAX_WIRE_BYTES];
  const size_t n = pv_link_encode_frame(msg, seq, wire, sizeof wire);
  if (n == 0) return PV_LINK_ENCODE_FAILED;

  if (cls == PV_LINK_LOSSY) {
    /* Only the newest lossy message matters: older unsent ones go. */
    for (uint32_t i = link->tx_count; i-- > 0;)
      if (slot_at(link, i)->lossy && removable(link, i)) remove_slot(link, i);
    if (link->tx_count == PV_LINK_TX_SLOTS) {
      link->stats.lossy_dropped++;
      if (fresh_seq) link->tx_seq++; /* the receiver sees the gap */
      return PV_LINK_DROPPED;
    }
  } else if (link->tx_count == PV_LINK_TX_SLOTS) {
    uint32_t i = link->tx_count;
    while (i-- > 0)
      if (slot_at(link, i)->lossy && removable(link, i)) break;
    if (i == UINT32_MAX) return PV_LINK_QUEUE_FULL;
    remove_slot(link, i);
  }
  pv_link_tx_slot_t *s = slot_at(link, link->tx_count);
  memcpy(s->bytes, wire, n);
  s->len = (uint16_t)n;
  s->lossy = cls == PV_LINK_LOSSY;
  link->tx_count++;
  if (fresh_seq) link->tx_seq++;
  return PV_LINK_OK;
}

pv_link_status_t pv_link_send(pv_link_t *link, const pitvol_Message *msg, pv_link_class_t cls,
                              uint32_t *seq_out) {
  if (!link || !msg) return PV_LINK_INVALID_ARGUMENT;
  const uint32_t seq = link->tx_seq;
  const pv_link_status_t st = enqueue(link, msg, cls, seq, 1);
  if (st == PV_LINK_OK && seq_out) *seq_out = seq;
  return st;
}

pv_link_status_t pv_link_send_again(pv_link_t *link, const pitvol_Message *msg, uint32_t seq) {
  if (!link || !msg) return PV_LINK_INVALID_ARGUMENT;
  return enqueue(link, msg, PV_LINK_RELIABLE, seq, 0);
}

pv_link_status_t pv_link_send_reply(pv_link_t *link, uint32_t command_seq,
                                    const pitvol_Message *reply) {
  if (!link || !reply) return PV_LINK_INVALID_ARGUMENT;
  if (link->cmd_have_seq && link->cmd_last_seq == command_seq) {
    link->reply = *reply;
    link->reply_valid = 1;
  }
  return pv_link_send(link, reply, PV_LINK_RELIABLE, NULL);
}

pv_link_status_t pv_link_ack(pv_link_t *link, uint32_t command_seq, uint32_t first_id,
                             uint32_t last_id, uint32_t sent_count) {
  if (!link) return PV_LINK_INVALID_ARGUMENT;
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_ack_tag;
  m.body.ack.command_seq = command_seq;
  m.body.ack.first_id = first_id;
  m.body.ack.last_id = last_id;
  m.body.ack.sent_count = sent_count;
  return pv_link_send_reply(link, command_seq, &m);
}

pv_link_status_t pv_link_nack(pv_link_t *link, uint32_t command_seq, pitvol_NackCode code,
                              const char *reason) {
  if (!link) return PV_LINK_INVALID_ARGUMENT;
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_nack_tag;
  m.body.nack.command_seq = command_seq;
  m.body.nack.code = (int32_t)code;
  if (reason) {
    strncpy(m.body.nack.reason, reason, sizeof m.body.nack.reason - 1);
  }
  return pv_link_send_reply(link, command_seq, &m);
}

int pv_link_tx_pending(const pv_link_t *link) { return link && link->tx_count > 0; }

pv_link_status_t pv_link_tx_flush(pv_link_t *link, pv_link_write_fn write, void *ctx) {
  if (!link || !write) return PV_LINK_INVALID_ARGUMENT;
  while (link->tx_count > 0) {
    pv_link_tx_slot_t *s = slot_at(link, 0);
    const size_t left = s->len - link->tx_written;
    const long r = write(ctx, s->bytes + link->tx_written, left);
    if (r < 0) return PV_LINK_WRITE_FAILED;
    link->tx_written += (uint32_t)r;
    if (link->tx_written < s->len) break; /* would block: poll for POLLOUT */
    link->tx_head = (link->tx_head + 1) % PV_LINK_TX_SLOTS;
    link->tx_count--;
    link->tx_written = 0;
    link->stats.frames_sent++;
  }
  return PV_LINK_OK;
}

int pv_link_is_command(const pitvol_Message *msg) {
  return msg && msg->which_body >= pitvol_Message_get_hello_tag &&
         msg->which_body <= pitvol_Message_get_results_tag;
}

const char *pv_link_message_name(const pitvol_Message *msg) {
  if (!msg) return "none";
  switch (msg->which_body) {
    case pitvol_Message_hello_tag: return "hello";
    case pitvol_Message_status_tag: return "status";
    case pitvol_Message_result_tag: return "result";
    case pitvol_Message_error_tag: return "error";
    case pitvol_Message_ack_tag: return "ack";
    case pitvol_Message_nack_tag: return "nack";
    case pitvol_Message_get_hello_tag: return "get_hello";
    case pitvol_Message_start_scan_tag: return "start_scan";
    case pitvol_Message_stop_scan_tag: return "stop_scan";
    case pitvol_Message_set_mass_tag: return "set_mass";
    case pitvol_Message_set_moisture_tag: return "set_moisture";
    case pitvol_Message_get_results_tag: return "get_results";
  }
  return "none";
}

/* One delimited frame body (COBS, no zeros). 1 if good: out filled. */
static int decode_frame(pv_link_t *link, pv_link_rx_t *out) {
  uint8_t raw[PV_LINK_MAX_RAW_BYTES];
  int ok = 0;
  const size_t n = pv_cobs_decode(link->rx, link->rx_len, raw, sizeof raw, &ok);
  pv_link_stats_t *st = &link->stats;
  if (!ok) {
    st->corrupt_cobs++; /* also: decodes to more than a frame's maximum */
    st->frames_corrupt++;
    return 0;
  }
  if (n < PV_LINK_HEADER_BYTES + PV_LINK_CRC_BYTES) {
    st->corrupt_length++;
    st->frames_corrupt++;
    return 0;
  }
  const size_t body = n - PV_LINK_CRC_BYTES;
  if (pv_crc32c(0, raw, body) != pv_get_le32(raw + body)) {
    st->corrupt_crc++;
    st->frames_corrupt++;
    return 0;
  }
  if (raw[0] != PV_LINK_FRAME_VERSION) {
    st->corrupt_version++;
    st->frames_corrupt++;
    return 0;
  }
  out->seq = pv_get_le32(raw + 1);
  pitvol_Message zero = pitvol_Message_init_zero;
  out->msg = zero;
  pb_istream_t is = pb_istream_from_buffer(raw + PV_LINK_HEADER_BYTES, body - PV_LINK_HEADER_BYTES);
  if (!pb_decode(&is, pitvol_Message_fields, &out->msg)) {
    st->corrupt_payload++;
    st->frames_corrupt++;
    return 0;
  }
  st->frames_received++;
  if (link->rx_have_seq) {
    const uint32_t ahead = out->seq - link->rx_last_seq; /* mod 2^32 */
    if (ahead != 0 && ahead <= PV_LINK_MAX_SEQ_GAP) {
      st->frames_missed += ahead - 1;
      link->rx_last_seq = out->seq;
    } else if (ahead > PV_LINK_MAX_SEQ_GAP && ahead < 0x80000000u) {
      /* No line loses a million frames: a host that restarted with a new
       * random first seq. Follow it; nothing was missed. */
      st->peer_restarts++;
      link->rx_last_seq = out->seq;
    }
  } else {
    link->rx_have_seq = 1;
    link->rx_last_seq = out->seq;
  }
  return 1;
}

/* 1 if the good frame in out is for the caller, 0 if the link answered a
 * repeated command itself. */
static int hand_on(pv_link_t *link, const pv_link_rx_t *rx) {
  if (!pv_link_is_command(&rx->msg)) return 1;
  if (link->cmd_have_seq && link->cmd_last_seq == rx->seq) {
    link->stats.commands_duplicate++;
    /* The answer got lost: send it again. A repeat that arrives before the
     * answer exists (a GetResults still streaming) is ignored, and so is a
     * refusal of a full queue: the host repeats the command again. */
    if (link->reply_valid) {
      const pv_link_status_t st = pv_link_send(link, &link->reply, PV_LINK_RELIABLE, NULL);
      (void)st;
    }
    return 0;
  }
  link->cmd_have_seq = 1;
  link->cmd_last_seq = rx->seq;
  link->reply_valid = 0;
  return 1;
}

size_t pv_link_feed(pv_link_t *link, const uint8_t *data, size_t len, pv_link_rx_t *out,
                    int *got) {
  if (got) *got = 0;
  if (!link || !data || !out || !got) return len;
  for (size_t i = 0; i < len; ++i) {
    const uint8_t b = data[i];
    if (b != 0) {
      if (link->rx_len < sizeof link->rx) link->rx[link->rx_len++] = b;
      else link->rx_overlong = 1;
      continue;
    }
    /* Delimiter: an empty frame is just the other delimiter of a pair. */
    if (link->rx_overlong) {
      link->stats.corrupt_length++;
      link->stats.frames_corrupt++;
    } else if (link->rx_len > 0 && decode_frame(link, out) && hand_on(link, out)) {
      link->rx_len = 0;
      *got = 1;
      return i + 1;
    }
    link->rx_len = 0;
    link->rx_overlong = 0;
  }
  return len;
}
