/*
 * systemd's service protocol for pitvol-board, without libsystemd: under a
 * unit with Type=notify and WatchdogSec= (packaging/pitvol-board.service)
 * the board says READY=1 once its devices are set up, then WATCHDOG=1 from
 * its own poll() loop every half watchdog period (a timerfd watched like
 * any other descriptor). A loop that stops turning stops the pings, and
 * systemd kills and restarts the service (Restart=on-failure).
 * Outside systemd ($NOTIFY_SOCKET unset) it does nothing.
 */
#ifndef PV_BOARD_WATCHDOG_H
#define PV_BOARD_WATCHDOG_H

#include <stddef.h>

#include "board_app.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 0, then 901 .. 949: PV_STATUS_BASE_WATCHDOG (pitvol/status_codes.h). */
typedef enum pv_board_watchdog_status {
  PV_BOARD_WATCHDOG_OK = 0,
  PV_BOARD_WATCHDOG_ERR_SOCKET_PATH = 901, /* $NOTIFY_SOCKET is not a socket path */
  PV_BOARD_WATCHDOG_ERR_NOTIFY = 902,      /* READY=1 could not be sent */
  PV_BOARD_WATCHDOG_ERR_TIMER = 903        /* the ping timer could not be set up */
} pv_board_watchdog_status_t;

/* The symbol ("PV_BOARD_WATCHDOG_ERR_NOTIFY"). Never NULL. */
const char *pv_board_watchdog_status_name(pv_board_watchdog_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_board_watchdog_status_message(pv_board_watchdog_status_t status);

/* After pv_board_app_init: READY=1 and, if $WATCHDOG_USEC asks for one
 * (and $WATCHDOG_PID is this process or unset), the ping timer.
 * PV_BOARD_WATCHDOG_OK (also outside systemd), or the fault with a
 * sentence in err (the socket, the system's reason). */
PV_NODISCARD pv_board_watchdog_status_t pv_board_watchdog_start(pv_board_app_t *app, char *err,
                                                                size_t errcap);
/* Closes the timer and the socket (after the loop has ended). */
void pv_board_watchdog_stop(void);

#ifdef __cplusplus
}
#endif
#endif
