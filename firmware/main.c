/* pitvol-board: the board application (docs/board.md). */
#include "board_cli.h"

int main(int argc, char **argv) {
  pv_board_block_signals();
  /* The serial link (issue 10) goes in here: hooks.after_init. */
  const pv_board_cli_hooks_t hooks = {0, 0};
  return pv_board_cli_main(argc, argv, &hooks);
}
