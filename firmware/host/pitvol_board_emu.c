/*
 * pitvol-board-emu: the board application on a host, with the scanner
 * emulated on umockdev (host_tools/usb_emulator) in the same process: the
 * same code as pitvol-board, the real libusb driver, the PNG display.
 *
 *   pitvol-board-emu FILE.frames [--fps F] [--unplug-at-frame N]
 *                    [--replug-after MS | --no-replug] [--absent-for MS]
 *                    [pitvol-board options: --config, --display, --input, --set]
 *     --fps F            pace the scanner to F frames per second (default 20)
 *     --unplug-at-frame N  unplug half way through frame N ...
 *     --replug-after MS    ... plug back after MS (default 300)
 *     --no-replug          ... and leave it unplugged
 *     --absent-for MS    no scanner at start; plugged in after MS
 *     --unplug-after MS  unplug MS after start, whatever the board is doing
 *                        (plugged back after --replug-after)
 *     --serial-pty LINK  the serial link on a pseudo-terminal pair joined by a
 *                        thread (host/noisy_line.h): the board has one
 *                        side, LINK becomes a symlink to the other
 *                        (pitvol-monitor LINK), kept open here so monitors
 *                        may come and go
 *     --serial-noise P   ... with line noise on P % of the bytes both ways
 *                        (bit flips, drops, inserted bytes)
 *     --serial-seed S    ... from seed S (default 1)
 *     --serial-by-path   ... and the board opens its side by name (the
 *                        `serial` key, pv_serial_open) as pitvol-board
 *                        does, instead of being handed the descriptor
 * Runs itself under umockdev-wrapper. At exit it prints the allocations
 * counted after start, per zone (board_alloc_zone.h).
 */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../board_alloc_zone.h"
#include "../board_cli.h"
#include "../board_link.h"
#include "alloc_counter.h"
#include "noisy_line.h"
#include "usb_emulator/emulated_scanner.h"

static pv_board_link_t g_link;
static int g_pty_master = -1; /* the board's side of the line */

static int link_start(pv_board_app_t *app, char *err, size_t errcap) {
  const int fd = g_pty_master;
  g_pty_master = -1; /* the link owns it now */
  return pv_board_link_start(&g_link, app, fd, err, errcap) == PV_BOARD_LINK_OK ? 0 : -1;
}

static void report_allocations(pv_board_app_t *app) {
  (void)app;
  pv_board_link_stop(&g_link);
  printf("pitvol-board: allocations after start: board=%ld push=%ld usb=%ld measure=%ld\n",
         pv_alloc_count(PV_ZONE_BOARD), pv_alloc_count(PV_ZONE_PUSH), pv_alloc_count(PV_ZONE_USB),
         pv_alloc_count(PV_ZONE_MEASURE));
}

typedef struct timed_unplug {
  pv_emu_t *emu;
  double after_ms;
} timed_unplug_t;

static void *unplug_later(void *p) {
  timed_unplug_t *t = (timed_unplug_t *)p;
  struct timespec ts = {(time_t)(t->after_ms / 1000), (long)(fmod(t->after_ms, 1000) * 1e6)};
  nanosleep(&ts, NULL);
  pv_emu_unplug(t->emu);
  return NULL;
}

static int usage(const char *why) {
  if (why != NULL) fprintf(stderr, "pitvol-board-emu: %s\n", why);
  fprintf(stderr,
          "usage: pitvol-board-emu FILE.frames [--fps F] [--unplug-at-frame N]\n"
          "         [--replug-after MS | --no-replug] [--absent-for MS] [--unplug-after MS]\n"
          "         [--serial-pty LINK [--serial-noise PERCENT] [--serial-seed S] [--serial-by-path]]\n"
          "         [pitvol-board options]\n");
  return 2;
}

static int number(const char *s, double *out) {
  char *end = NULL;
  *out = strtod(s, &end);
  return end != s && *end == '\0' && isfinite(*out) && *out >= 0;
}

int main(int argc, char **argv) {
  if (argc < 2) return usage(NULL);
  if (!pv_emu_available() && getenv("PITVOL_BOARD_EMU_NO_REEXEC") == NULL) {
    setenv("PITVOL_BOARD_EMU_NO_REEXEC", "1", 1);
    char **args = calloc((size_t)argc + 2, sizeof *args);
    if (args == NULL) return 3;
    args[0] = (char *)"umockdev-wrapper";
    for (int i = 0; i < argc; ++i) args[i + 1] = argv[i];
    execvp("umockdev-wrapper", args);
    fprintf(stderr, "pitvol-board-emu: cannot run umockdev-wrapper (%s); install umockdev\n",
            strerror(errno));
    return 3;
  }
  pv_board_block_signals(); /* before the emulator's threads exist */

  const char *frames = NULL, *pty_link = NULL;
  double noise_percent = 0, noise_seed = 1;
  int by_path = 0;
  char serial_arg[96];
  double fps = 20, absent_ms = -1, unplug_after_ms = -1, v = 0;
  pv_emu_options_t eo;
  pv_emu_options_default(&eo);
  eo.replug_after_ms = 300;
  int board_argc = 1;
  char **board_argv = calloc((size_t)argc + 3, sizeof *board_argv); /* + --set serial=... */
  if (board_argv == NULL) return 3;
  board_argv[0] = argv[0];
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const int more = i + 1 < argc;
    if (strcmp(a, "--fps") == 0 && more && number(argv[i + 1], &v) && v > 0) {
      fps = v, ++i;
    } else if (strcmp(a, "--unplug-at-frame") == 0 && more && number(argv[i + 1], &v)) {
      eo.unplug_at_frame = (int64_t)v, ++i;
    } else if (strcmp(a, "--replug-after") == 0 && more && number(argv[i + 1], &v)) {
      eo.replug_after_ms = (int)v, ++i;
    } else if (strcmp(a, "--no-replug") == 0) {
      eo.replug_after_ms = -1;
    } else if (strcmp(a, "--unplug-after") == 0 && more && number(argv[i + 1], &v)) {
      unplug_after_ms = v, ++i;
    } else if (strcmp(a, "--absent-for") == 0 && more && number(argv[i + 1], &v)) {
      absent_ms = v, ++i;
    } else if (strcmp(a, "--serial-pty") == 0 && more) {
      pty_link = argv[++i];
    } else if (strcmp(a, "--serial-noise") == 0 && more && number(argv[i + 1], &v) && v <= 50) {
      noise_percent = v, ++i;
    } else if (strcmp(a, "--serial-by-path") == 0) {
      by_path = 1;
    } else if (strcmp(a, "--serial-seed") == 0 && more && number(argv[i + 1], &v)) {
      noise_seed = v, ++i;
    } else if (a[0] != '-' && frames == NULL) {
      frames = a;
    } else {
      board_argv[board_argc++] = argv[i];
      if (more && argv[i + 1][0] != '-') board_argv[board_argc++] = argv[++i];
    }
  }
  if (frames == NULL) return usage("a .frames file is required");

  char err[512] = "";
  pv_emu_t *emu = NULL;
  /* Pace by the file's average frame size (as pitvol-usb-replay --fps). */
  pv_emu_t *probe = NULL;
  pv_emu_options_t po;
  pv_emu_options_default(&po);
  if (pv_emu_create_from_file(&probe, frames, &po, err, sizeof err) != 0) {
    fprintf(stderr, "pitvol-board-emu: %s: %s\n", frames, err);
    return 3;
  }
  pv_emu_stats_t ps;
  pv_emu_stats(probe, &ps);
  pv_emu_destroy(probe);
  eo.interval_ms = 10;
  eo.bytes_per_interval = (uint32_t)ceil((double)ps.bytes_out / (double)ps.frames_out * fps / 100.0);

  if (absent_ms >= 0) {
    /* One replug delay in the emulator: --absent-for sets it. */
    eo.replug_after_ms = (int)absent_ms;
    if (pv_emu_create_from_file(&emu, frames, &eo, err, sizeof err) != 0 || pv_emu_unplug(emu) != 0) {
      fprintf(stderr, "pitvol-board-emu: %s: %s\n", frames, err);
      return 3;
    }
    /* The removal happens on the emulator's thread: let it finish before
     * libusb enumerates. */
    struct timespec ts = {0, 100 * 1000000L};
    nanosleep(&ts, NULL);
  } else if (pv_emu_create_from_file(&emu, frames, &eo, err, sizeof err) != 0) {
    fprintf(stderr, "pitvol-board-emu: %s: %s\n", frames, err);
    return 3;
  }
  printf("pitvol-board-emu: scanner emulated from %s (%llu frames, %.0f fps)%s\n", frames,
         (unsigned long long)ps.frames_out, fps, absent_ms >= 0 ? ", absent at start" : "");
  timed_unplug_t tu = {emu, unplug_after_ms};
  pthread_t unplugger;
  const int timed = unplug_after_ms >= 0 && pthread_create(&unplugger, NULL, unplug_later, &tu) == 0;
  static pv_noisy_line_t line;
  if (pty_link != NULL) {
    if (pv_noisy_line_open(&line, pty_link, noise_percent, (uint64_t)noise_seed, err, sizeof err) != 0) {
      fprintf(stderr, "pitvol-board-emu: serial line: %s\n", err);
      return 3;
    }
    if (by_path) { /* the emulator keeps its descriptor; the board opens the name */
      snprintf(serial_arg, sizeof serial_arg, "serial=%s", line.board_name);
      board_argv[board_argc++] = (char *)"--set";
      board_argv[board_argc++] = serial_arg;
    } else {
      g_pty_master = line.board_fd;
    }
    printf("pitvol-board-emu: serial link on %s, noise %.3g %% of bytes\n", pty_link, noise_percent);
  }
  const pv_board_cli_hooks_t hooks = {link_start, report_allocations};
  const int rc = pv_board_cli_main(board_argc, board_argv, &hooks);
  if (timed) pthread_join(unplugger, NULL);
  if (pty_link != NULL) {
    pv_noisy_line_close(&line);
    if (by_path) close(line.board_fd);
    printf("pitvol-board-emu: serial line: %lu bytes, %lu hit by noise\n", line.bytes, line.hit);
    unlink(pty_link);
  }
  if (g_pty_master >= 0) close(g_pty_master);
  pv_emu_destroy(emu);
  free(board_argv);
  return rc;
}
