/*
 * The device end of the serial link (docs/protocol/serial.md, "What the
 * board application does"): answers the host's commands, streams the result
 * log, sends each result and the status. The board (firmware/board_link.c)
 * and the monitor's test device (tests/monitor/pv_test_device.cpp) both run
 * this server; each gives it its application as a pv_link_app_t of
 * callbacks and owns the port, the clock and the loop:
 *
 *   static pv_link_server_t srv;  pv_link_server_init(&srv, &cfg);
 *   on bytes read:        pv_link_server_feed(&srv, buf, n);
 *   on a result:          pv_link_server_log_result(), _send_result()
 *   every status period:  pv_link_server_send_status(&srv);
 *   after any of these:   pv_link_server_service(&srv, write_fn, ctx);
 *                         poll for POLLOUT while pv_link_tx_pending(&srv.link)
 *
 *  - GetHello: Hello, then Ack. GetResults: the log's records from_id ..
 *    to_id streamed as the link's queue drains (a record that does not
 *    decode is skipped: Ack.sent_count tells the host), then the Ack; a
 *    record the queue refused is read again from the log after a flush.
 *  - SetMass, SetMoisture: checked against pitvol/user_input.h, then handed
 *    to the application; SetRecord: applied to the application's record,
 *    all fields or none.
 *  - StartScan, StopScan: the application decides (Ack or Nack).
 *  - An answer waits behind the messages its command produced and is kept
 *    by the link for a repeated command (pv_link_send_reply).
 * No allocation: the link, the outbox and the fetch are in this struct.
 */
#ifndef PITVOL_LINK_SERVER_H
#define PITVOL_LINK_SERVER_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/link.h"
#include "pitvol/link_result.h"
#include "pitvol/result_log.h"
#include "pitvol/status_codes.h"
#include "pitvol/user_input.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_LINK_SERVER_OUTBOX 8u /* reliable messages waiting for queue room */

/* Error.code of a board fault: the result log refused a record. The first
 * code of the board's range (pitvol/status_codes.h), on the wire since
 * protocol 1, with Error.name "PV_BOARD_LOG". */
#define PV_LINK_SERVER_ERR_LOG PV_STATUS_BASE_BOARD

/* The application behind the server. ctx is pv_link_server_config_t.ctx.
 * Every callback is required except note. */
typedef struct pv_link_app {
  /* The device's part of a Status: state, points, running volume and
   * coverage, mass and moisture. The server fills last_result_id and
   * frames_corrupt. */
  void (*status)(void *ctx, pitvol_Status *out);
  /* StartScan, StopScan: NACK_NONE to acknowledge, else the refusal's code
   * with a sentence for the user in why (cap bytes). */
  pitvol_NackCode (*start_scan)(void *ctx, char *why, size_t cap);
  pitvol_NackCode (*stop_scan)(void *ctx, char *why, size_t cap);
  /* A mass (g) or moisture (%) in its plausible range, for the next result. */
  void (*set_density_input)(void *ctx, pv_input_kind_t kind, double value);
  /* The record the next result is taken under, and its new value after a
   * SetRecord. */
  void (*get_record)(void *ctx, pv_link_record_t *out);
  void (*set_record)(void *ctx, const pv_link_record_t *rec);
  /* Optional: one line for the device's log (a command received, a message
   * dropped, a log record skipped). */
  void (*note)(void *ctx, const char *line);
} pv_link_app_t;

typedef struct pv_link_server_config {
  const pv_link_app_t *app;
  void *ctx;
  pv_log_t *log;             /* opened result log, or NULL: none (GetResults refused) */
  const char *device_id;     /* Hello.device_id */
  uint32_t capabilities;     /* Hello.capabilities; CAP_RESULT_LOG is added with a log */
  uint32_t first_seq;        /* the link's first frame number (pv_link_init) */
} pv_link_server_config_t;

typedef struct pv_link_server_out {
  pitvol_Message msg;
  uint8_t is_reply;
  uint32_t reply_to;
} pv_link_server_out_t;

typedef struct pv_link_server {
  pv_link_t link;
  pv_link_server_config_t cfg;
  pv_link_server_out_t outbox[PV_LINK_SERVER_OUTBOX];
  uint32_t out_head, out_len;
  uint32_t out_dropped; /* reliable messages dropped with the outbox full */
  struct {
    int on;
    uint32_t cmd_seq, to_id, sent;
    pv_log_cursor_t cur;
  } fetch;
} pv_link_server_t;

void pv_link_server_init(pv_link_server_t *srv, const pv_link_server_config_t *cfg);

/* Bytes read from the port: every command completed in them is answered
 * (queued; pv_link_server_service sends). Corrupt frames are counted in
 * srv->link.stats. */
void pv_link_server_feed(pv_link_server_t *srv, const uint8_t *data, size_t len);

/* Moves the outbox and the log fetch into the link's queue and writes as
 * far as write takes them. PV_LINK_OK (frames may still wait: poll for
 * POLLOUT while pv_link_tx_pending) or PV_LINK_WRITE_FAILED. */
PV_NODISCARD pv_link_status_t pv_link_server_service(pv_link_server_t *srv, pv_link_write_fn write,
                                                     void *write_ctx);

/* A Status now (lossy: a newer one replaces it, a full queue drops it and
 * the link counts it in lossy_dropped). */
void pv_link_server_send_status(pv_link_server_t *srv);

/* Appends r to the log (fsync'd) and sets r->id to its record number.
 * PV_LOG_OK, or the log's status with r->id 0; PV_LOG_OK with r->id 0
 * when there is no log. */
PV_NODISCARD pv_log_status_t pv_link_server_log_result(pv_link_server_t *srv, pitvol_Result *r);

/* Sends a result once logged (logged: what pv_link_server_log_result
 * said): an Error PV_BOARD_LOG first if the log refused it, the Result, an
 * Error naming the status when it has no volume, then a Status with its id. */
void pv_link_server_send_result(pv_link_server_t *srv, const pitvol_Result *r,
                                pv_log_status_t logged);

/* 1 while answers or a log fetch wait to enter the link's queue or frames
 * wait to be written, else 0. */
int pv_link_server_busy(const pv_link_server_t *srv);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_LINK_SERVER_H */
