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

/* After pv_board_app_init: READY=1 and, if $WATCHDOG_USEC asks for one
 * (and $WATCHDOG_PID is this process or unset), the ping timer. 0, or -1
 * with a sentence in err. */
PV_NODISCARD int pv_board_watchdog_start(pv_board_app_t *app, char *err, size_t errcap);
/* Closes the timer and the socket (after the loop has ended). */
void pv_board_watchdog_stop(void);

#ifdef __cplusplus
}
#endif
#endif
