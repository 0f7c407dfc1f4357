/*
 * pitvol-board [--config FILE] [--display SPEC] [--input SPEC]
 *              [--set KEY=VALUE ...]
 * Defaults: /etc/pitvol/board.conf if it exists, else the built-in board
 * defaults; options after the file override it (docs/board.md).
 * Exit codes: 0 stopped by SIGTERM/SIGINT, 2 usage or configuration,
 * 3 a device could not be set up.
 */
#include "board_cli.h"

#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "board_app.h"

#define PV_BOARD_DEFAULT_CONFIG "/etc/pitvol/board.conf"

static char g_stdout_buf[8192]; /* stdout without a heap buffer */
static pv_board_app_t g_app;    /* large: static, not on the stack */

void pv_board_block_signals(void) {
  sigset_t mask;
  sigemptyset(&mask);
  sigaddset(&mask, SIGTERM);
  sigaddset(&mask, SIGINT);
  pthread_sigmask(SIG_BLOCK, &mask, NULL);
  signal(SIGPIPE, SIG_IGN);
}

static int usage(const char *why) {
  if (why != NULL) fprintf(stderr, "pitvol-board: %s\n", why);
  fprintf(stderr,
          "usage: pitvol-board [--config FILE] [--display fbdev:/dev/fbN|png:DIR]\n"
          "                    [--input evdev:/dev/input/eventN|pipe:PATH|none]\n"
          "                    [--set KEY=VALUE ...]\n");
  return 2;
}

/* A refused configuration: the sentence and the status's name. */
static int config_usage(pv_board_config_status_t st, const char *err) {
  char why[640];
  snprintf(why, sizeof why, "%s [%s]", err, pv_board_config_status_name(st));
  return usage(why);
}

int pv_board_cli_main(int argc, char **argv, const pv_board_cli_hooks_t *hooks) {
  setvbuf(stdout, g_stdout_buf, _IOLBF, sizeof g_stdout_buf);
  pv_board_config_t cfg;
  pv_board_config_default(&cfg);
  char err[512];
  const char *config = NULL;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) config = argv[++i];
  }
  if (config == NULL && access(PV_BOARD_DEFAULT_CONFIG, R_OK) == 0) config = PV_BOARD_DEFAULT_CONFIG;
  pv_board_config_status_t st = PV_BOARD_CONFIG_OK;
  if (config != NULL) st = pv_board_config_load(&cfg, config, err, sizeof err);
  if (st != PV_BOARD_CONFIG_OK) return config_usage(st, err);
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const int more = i + 1 < argc;
    if (strcmp(a, "--config") == 0 && more) {
      ++i;
    } else if ((strcmp(a, "--display") == 0 || strcmp(a, "--input") == 0) && more) {
      st = pv_board_config_set(&cfg, a + 2, argv[++i], err, sizeof err);
      if (st != PV_BOARD_CONFIG_OK) return config_usage(st, err);
    } else if (strcmp(a, "--set") == 0 && more) {
      char kv[512];
      snprintf(kv, sizeof kv, "%s", argv[++i]);
      char *eq = strchr(kv, '=');
      if (eq == NULL) return usage("--set wants KEY=VALUE");
      *eq = '\0';
      st = pv_board_config_set(&cfg, kv, eq + 1, err, sizeof err);
      if (st != PV_BOARD_CONFIG_OK) return config_usage(st, err);
    } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      return usage(NULL);
    } else {
      char why[256];
      snprintf(why, sizeof why, "unknown or incomplete option '%s'", a);
      return usage(why);
    }
  }
  st = pv_board_config_check(&cfg, err, sizeof err);
  if (st != PV_BOARD_CONFIG_OK) return config_usage(st, err);
  printf("pitvol-board %s: display %s, input %s, scanner %04x:%04x\n", PV_VERSION_STRING,
         cfg.display, cfg.input, cfg.usb_vendor, cfg.usb_product);
  if (pv_board_app_init(&g_app, &cfg, err, sizeof err) != PV_BOARD_APP_OK) {
    fprintf(stderr, "pitvol-board: %s\n", err);
    pv_board_app_close(&g_app);
    return 3;
  }
  if (hooks != NULL && hooks->after_init != NULL && hooks->after_init(&g_app, err, sizeof err) != 0) {
    fprintf(stderr, "pitvol-board: %s\n", err);
    pv_board_app_close(&g_app);
    return 3;
  }
  const pv_board_app_status_t rc = pv_board_app_run(&g_app, err, sizeof err);
  if (hooks != NULL && hooks->after_run != NULL) hooks->after_run(&g_app);
  pv_board_app_close(&g_app);
  if (rc != PV_BOARD_APP_OK) fprintf(stderr, "pitvol-board: %s\n", err);
  fflush(stdout);
  return rc == PV_BOARD_APP_OK ? 0 : 3;
}
