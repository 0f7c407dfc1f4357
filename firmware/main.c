/* pitvol-board: the board application (docs/board.md). */
#include "board_cli.h"
#include "board_link.h"

static pv_board_link_t g_link; /* the serial link and result log: static, no allocation */

static int link_start(pv_board_app_t *app, char *err, size_t errcap) {
  return pv_board_link_start(&g_link, app, -1, err, errcap);
}
static void link_stop(pv_board_app_t *app) {
  (void)app;
  pv_board_link_stop(&g_link);
}

int main(int argc, char **argv) {
  pv_board_block_signals();
  const pv_board_cli_hooks_t hooks = {link_start, link_stop};
  return pv_board_cli_main(argc, argv, &hooks);
}
