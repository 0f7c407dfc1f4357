/*
 * The board's serial link and result log (docs/protocol/serial.md
 * "What the board application does"): the link server (pitvol/link_server.h)
 * with the board application as its application, attached through the
 * board's hooks (pv_board_app_watch, _post, _set_observer).
 *  - opens the result log (config result_log) and the port (config serial,
 *    serial_baud); an absent or unopenable port means no link, said in the
 *    board's log, and the board measures as before;
 *  - takes StartScan/StopScan as the START/STOP button's event,
 *    SetMass/SetMoisture into the model (used by the next result), SetRecord
 *    into the model's test id and the configuration's record;
 *  - sends Status twice a second while scanning (every 2 s otherwise, and
 *    on every state change), appends each Result to the log (fsync) and only
 *    then sends it, with an Error when the scan gave no volume.
 * No allocation after start: the server (link, outbox) and the log are in
 * this struct.
 */
#ifndef PV_BOARD_LINK_H
#define PV_BOARD_LINK_H

#include <stddef.h>
#include <stdint.h>

#include "board_app.h"
#include "pitvol/link_server.h"
#include "pitvol/result_log.h"
#include "pitvol/serial.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_BOARD_LINK_STATUS_MS 500u /* Status period while scanning */

typedef struct pv_board_link {
  pv_board_app_t *app;
  int have_port, have_log;
  pv_serial_t port;
  pv_log_t log;
  pv_link_server_t srv;
  int timer_fd;
  unsigned ticks;
  int write_failed; /* said once in the log */
} pv_board_link_t;

/* 0, then 1001 .. 1049: PV_STATUS_BASE_BOARD_LINK (pitvol/status_codes.h). */
typedef enum pv_board_link_status {
  PV_BOARD_LINK_OK = 0,
  PV_BOARD_LINK_ERR_LOG = 1001,   /* the result log cannot be opened */
  PV_BOARD_LINK_ERR_TIMER = 1002, /* the link's status timer cannot be set up */
  PV_BOARD_LINK_ERR_WATCH = 1003  /* the board's loop does not take the port or the timer */
} pv_board_link_status_t;

/* The symbol ("PV_BOARD_LINK_ERR_LOG"). Never NULL. */
const char *pv_board_link_status_name(pv_board_link_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_board_link_status_message(pv_board_link_status_t status);

/* After pv_board_app_init. adopt_fd >= 0: a terminal fd to use instead of
 * opening cfg.serial (the host runner's pseudo-terminal); the link closes
 * it. PV_BOARD_LINK_OK (also when the port does not open: the board then
 * runs without a link and says so), or the fault with a sentence in err. */
PV_NODISCARD pv_board_link_status_t pv_board_link_start(pv_board_link_t *bl, pv_board_app_t *app,
                                                        int adopt_fd, char *err, size_t errcap);
/* After the loop: flushes what it can, prints the link's counters, closes. */
void pv_board_link_stop(pv_board_link_t *bl);

#ifdef __cplusplus
}
#endif
#endif
