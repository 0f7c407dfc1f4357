/* pitvol-board's command line, shared by the board program (main.c) and the
 * host runner with the emulated scanner (host/pitvol_board_emu.c). */
#ifndef PV_BOARD_CLI_H
#define PV_BOARD_CLI_H

#ifdef __cplusplus
extern "C" {
#endif

/* Parses the options, sets the board up, runs it until SIGTERM/SIGINT.
 * after_run (may be NULL) is called when the loop has ended, before
 * anything is freed. Returns the process exit code. Call
 * pv_board_block_signals() first, before any thread exists. */
int pv_board_cli_main(int argc, char **argv, void (*after_run)(void));
/* Blocks SIGTERM and SIGINT in this thread and every thread created later:
 * the event loop takes them from its signalfd. */
void pv_board_block_signals(void);

#ifdef __cplusplus
}
#endif
#endif
