/*
 * pitvol serial link: frames pitvol_link.proto messages on a byte stream
 * (docs/protocol/serial.md). The board and pitvol-monitor both use it.
 *
 * Frame on the wire:   0x00  COBS( version | seq | payload | crc32c )  0x00
 *   version  1 byte      PV_LINK_FRAME_VERSION
 *   seq      4 bytes LE  sender's frame counter, +1 per frame
 *   payload  0..PV_LINK_MAX_PAYLOAD_BYTES  nanopb-encoded pitvol.Message
 *   crc32c   4 bytes LE  CRC-32C of version .. payload
 *
 * Made for a single-threaded event loop, no allocation, no blocking:
 *
 *   static pv_link_t link;  pv_link_init(&link, first_seq);
 *   loop:
 *     poll(fd, POLLIN | (pv_link_tx_pending(&link) ? POLLOUT : 0))
 *     on POLLIN:  n = read(...);  for (p = buf; n; ) {
 *                   size_t used = pv_link_feed(&link, p, n, &rx, &got);
 *                   p += used; n -= used;  if (got) handle(&rx); }
 *     on POLLOUT: pv_link_tx_flush(&link, write_fn, ctx);
 *     anywhere:   pv_link_send(&link, &msg, PV_LINK_LOSSY or _RELIABLE, NULL);
 *
 * The outgoing queue is bounded (PV_LINK_TX_SLOTS encoded frames). Lossy
 * messages (Status) are replaced by a newer one or dropped when the queue
 * is full; reliable ones (Result, Ack, Nack, Error, Hello) evict queued lossy
 * ones and are refused with PV_LINK_QUEUE_FULL only when the queue holds
 * nothing but reliable frames: the caller keeps them (a Result stays in the
 * log) and sends again after a flush. So a slow or absent host never blocks
 * the board and never loses a result.
 */
#ifndef PITVOL_LINK_H
#define PITVOL_LINK_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol_link.pb.h"
#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_LINK_PROTOCOL_VERSION 1u /* Hello.protocol_version */
#define PV_LINK_FRAME_VERSION 1u    /* first byte of every frame */
#define PV_LINK_HEADER_BYTES 5u     /* version + seq */
#define PV_LINK_CRC_BYTES 4u
#define PV_LINK_MAX_PAYLOAD_BYTES ((size_t)pitvol_Message_size)
#define PV_LINK_MAX_RAW_BYTES (PV_LINK_HEADER_BYTES + PV_LINK_MAX_PAYLOAD_BYTES + PV_LINK_CRC_BYTES)
/* COBS body without delimiters. */
#define PV_LINK_MAX_COBS_BYTES (PV_LINK_MAX_RAW_BYTES + PV_LINK_MAX_RAW_BYTES / 254u + 1u)
/* Largest frame on the wire, both delimiters included (Hello.max_frame_bytes). */
#define PV_LINK_MAX_WIRE_BYTES (PV_LINK_MAX_COBS_BYTES + 2u)
#define PV_LINK_TX_SLOTS 8u
/* A larger forward jump of the peer's seq is a new peer (a host restarts at
 * a random seq), counted in peer_restarts, not as missed frames. */
#define PV_LINK_MAX_SEQ_GAP 65536u

typedef enum pv_link_status {
  /* 0, then 500 .. 599: PV_STATUS_BASE_LINK (pitvol/status_codes.h) */
  PV_LINK_OK = 0,
  PV_LINK_DROPPED = 501,          /* a lossy message was dropped (queue full of reliable ones) */
  PV_LINK_QUEUE_FULL = 502,       /* a reliable message was refused: flush, then send again */
  PV_LINK_ENCODE_FAILED = 503,    /* the message does not encode (a string too long?) */
  PV_LINK_INVALID_ARGUMENT = 504, /* NULL pointer */
  PV_LINK_WRITE_FAILED = 505,     /* the write callback reported an error */
  PV_LINK_RECORD_TEXT = 506,      /* a SetRecord's text is too long or has a control character */
  PV_LINK_RECORD_OUT_OF_RANGE = 507 /* a SetRecord's number lies outside its range */
} pv_link_status_t;

/* Short name and a sentence for the user. Never NULL. */
const char *pv_link_status_name(pv_link_status_t status);
const char *pv_link_status_message(pv_link_status_t status);

typedef enum pv_link_class {
  PV_LINK_LOSSY = 0,    /* may be replaced or dropped (Status) */
  PV_LINK_RELIABLE = 1  /* never dropped once queued */
} pv_link_class_t;

/* Counters since init. Corrupt frames are counted by cause. */
typedef struct pv_link_stats {
  uint32_t frames_sent;        /* completely written by pv_link_tx_flush */
  uint32_t frames_received;    /* good frames handed to the caller (duplicates included) */
  uint32_t frames_corrupt;     /* sum of the five causes below */
  uint32_t corrupt_cobs;       /* not valid COBS */
  uint32_t corrupt_length;     /* shorter than a header + CRC, or longer than the maximum */
  uint32_t corrupt_crc;        /* CRC-32C mismatch */
  uint32_t corrupt_version;    /* frame version this side does not speak */
  uint32_t corrupt_payload;    /* CRC good but the payload is not a pitvol.Message */
  uint32_t frames_missed;      /* gaps in the peer's sequence numbers */
  uint32_t peer_restarts;      /* seq jumps beyond PV_LINK_MAX_SEQ_GAP: a new peer */
  uint32_t lossy_dropped;      /* lossy messages replaced or dropped before sending */
  uint32_t commands_duplicate; /* a repeated command: answered again, not handed on */
} pv_link_stats_t;

/* A received message and the sequence number of its frame (an Ack or Nack
 * must name it as command_seq). */
typedef struct pv_link_rx {
  uint32_t seq;
  pitvol_Message msg;
} pv_link_rx_t;

typedef struct pv_link_tx_slot {
  uint16_t len;
  uint8_t lossy;
  uint8_t bytes[PV_LINK_MAX_WIRE_BYTES];
} pv_link_tx_slot_t;

/* The whole link state; place it anywhere (static, stack, a struct). */
typedef struct pv_link {
  pv_link_tx_slot_t tx[PV_LINK_TX_SLOTS]; /* ring of encoded frames */
  uint32_t tx_head, tx_count;  /* oldest slot, slots in use */
  uint32_t tx_written;         /* bytes of the oldest slot already written */
  uint32_t tx_seq;             /* sequence number of the next frame */

  uint8_t rx[PV_LINK_MAX_COBS_BYTES]; /* bytes since the last delimiter */
  uint32_t rx_len;
  uint8_t rx_overlong;         /* too many bytes: skip to the next delimiter */
  uint8_t rx_have_seq;
  uint32_t rx_last_seq;

  /* Repeated commands (the host re-sends when an Ack got lost). */
  uint8_t cmd_have_seq, reply_valid;
  uint32_t cmd_last_seq;
  pitvol_Message reply;        /* the Ack/Nack sent for cmd_last_seq */

  pv_link_stats_t stats;
} pv_link_t;

/* first_seq: the sequence number of the first frame sent. A host should
 * pick it at random so that a board does not take its first command for a
 * repeat of the previous host's. */
void pv_link_init(pv_link_t *link, uint32_t first_seq);

/* Encodes msg into the outgoing queue. seq_out (may be NULL) receives the
 * frame's sequence number. PV_LINK_OK, PV_LINK_DROPPED (lossy only),
 * PV_LINK_QUEUE_FULL (reliable only), PV_LINK_ENCODE_FAILED. */
PV_NODISCARD pv_link_status_t pv_link_send(pv_link_t *link, const pitvol_Message *msg,
                                           pv_link_class_t cls, uint32_t *seq_out);

/* Queues msg again under the sequence number it was first sent with
 * (reliable): a host repeating a command whose answer did not come, so the
 * board can tell the repeat from a new command. */
PV_NODISCARD pv_link_status_t pv_link_send_again(pv_link_t *link, const pitvol_Message *msg,
                                                 uint32_t seq);

/* Answers the command received in frame command_seq (reliable, and kept so
 * that a repeat of the command is answered again without reaching the
 * caller). first_id/last_id/sent_count: see pitvol.Ack. */
PV_NODISCARD pv_link_status_t pv_link_ack(pv_link_t *link, uint32_t command_seq, uint32_t first_id,
                                          uint32_t last_id, uint32_t sent_count);
PV_NODISCARD pv_link_status_t pv_link_nack(pv_link_t *link, uint32_t command_seq,
                                           pitvol_NackCode code, const char *reason);
/* The same for a ready Ack or Nack message (e.g. one held back until the
 * messages it follows have gone out). The answer is kept for repeats even
 * when this returns PV_LINK_QUEUE_FULL; call again after a flush. */
PV_NODISCARD pv_link_status_t pv_link_send_reply(pv_link_t *link, uint32_t command_seq,
                                                 const pitvol_Message *reply);

/* 1 if frames wait to be written (poll for POLLOUT), else 0. */
int pv_link_tx_pending(const pv_link_t *link);
/* Reliable frames that can still be queued right now. */
uint32_t pv_link_tx_room(const pv_link_t *link);

/* Non-blocking write: returns bytes taken (0 if it would block), or < 0 on
 * an error. pv_link_tx_flush() calls it until the queue is empty or it
 * takes less than offered. */
typedef long (*pv_link_write_fn)(void *ctx, const uint8_t *data, size_t len);
PV_NODISCARD pv_link_status_t pv_link_tx_flush(pv_link_t *link, pv_link_write_fn write, void *ctx);

/* Feeds received bytes. Consumes bytes up to and including the first frame
 * that completes; if that frame is good, *got = 1 and *out holds it.
 * Returns the bytes consumed (call again with the rest). Corrupt frames are
 * counted in stats and skipped; the reader resynchronises at the next zero. */
size_t pv_link_feed(pv_link_t *link, const uint8_t *data, size_t len, pv_link_rx_t *out,
                    int *got);

/* 1 if msg is a host -> board command (GetHello .. GetResults). */
int pv_link_is_command(const pitvol_Message *msg);
/* "hello", "status", "result", ... for logs; "none" if unset. */
const char *pv_link_message_name(const pitvol_Message *msg);

/* One frame without the queue (tests, tools): encodes msg with seq into
 * out (cap bytes, both delimiters included). Returns the length or 0. */
PV_NODISCARD size_t pv_link_encode_frame(const pitvol_Message *msg, uint32_t seq, uint8_t *out,
                                         size_t cap);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_LINK_H */
