/* pitvol-board's command line, shared by the board program (main.c) and the
 * host runner with the emulated scanner (host/pitvol_board_emu.c). */
#ifndef PV_BOARD_CLI_H
#define PV_BOARD_CLI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pv_board_app pv_board_app_t;

/* Where a program adds to the board (every member may be NULL). */
typedef struct pv_board_cli_hooks {
  /* After the board is set up, before the loop: the serial link
   * opens the `serial` port here and registers it with pv_board_app_watch()
   * and pv_board_app_set_observer(). 0, or -1 with a sentence in err
   * (the program then stops with exit code 3). */
  int (*after_init)(pv_board_app_t *app, char *err, size_t errcap);
  /* When the loop has ended, before anything is freed. */
  void (*after_run)(pv_board_app_t *app);
} pv_board_cli_hooks_t;

/* Parses the options, sets the board up, runs it until SIGTERM/SIGINT.
 * Returns the process exit code. Call pv_board_block_signals() first,
 * before any thread exists. */
int pv_board_cli_main(int argc, char **argv, const pv_board_cli_hooks_t *hooks);
/* Blocks SIGTERM and SIGINT in this thread and every thread created later:
 * the event loop takes them from its signalfd. */
void pv_board_block_signals(void);

#ifdef __cplusplus
}
#endif
#endif
