/* pitvol-board: the board application (docs/board.md). */
#include "board_cli.h"

int main(int argc, char **argv) {
  pv_board_block_signals();
  return pv_board_cli_main(argc, argv, 0);
}
