/* pitvol-board: the board application (docs/board.md). */
#include "board_cli.h"
#include "board_link.h"
#include "board_watchdog.h"

#include <stdio.h>
#include <string.h>

static pv_board_link_t g_link; /* the serial link and result log: static, no allocation */

static int after_init(pv_board_app_t *app, char *err, size_t errcap) {
  if (pv_board_link_start(&g_link, app, -1, err, errcap) != PV_BOARD_LINK_OK) return -1;
  const pv_board_watchdog_status_t st = pv_board_watchdog_start(app, err, errcap);
  if (st != PV_BOARD_WATCHDOG_OK) {
    /* The log names the fault; the board does not run unwatched under a
     * unit that asked for a watchdog. */
    const size_t n = strnlen(err, errcap);
    if (n < errcap) snprintf(err + n, errcap - n, " [%s]", pv_board_watchdog_status_name(st));
    return -1;
  }
  return 0;
}
static void after_run(pv_board_app_t *app) {
  (void)app;
  pv_board_watchdog_stop();
  pv_board_link_stop(&g_link);
}

int main(int argc, char **argv) {
  pv_board_block_signals();
  const pv_board_cli_hooks_t hooks = {after_init, after_run};
  return pv_board_cli_main(argc, argv, &hooks);
}
