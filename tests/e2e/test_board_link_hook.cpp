// The hook the serial link (firmware/board_link.c) uses, exercised in-process
// with the emulated scanner: a descriptor registered with pv_board_app_watch()
// carries commands, the callback feeds them in with pv_board_app_post(),
// and the observer hears every state, live estimate and the result. A pipe
// stands in for the serial port here; the board's own buttons are "none".
// Runs under umockdev-wrapper (exit 77 without it). Argument: a .frames file.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include "board_app.h"
#include "board_cli.h"
}
#include "usb_emulator/emulated_scanner.h"

#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

const char *g_frames = nullptr;
pv_board_app_t g_app;  // large: static

struct Link {
  int rd = -1, wr = -1;
  std::vector<pv_board_state_t> states;
  int estimates = 0;
  int results = 0;
  pv_board_model_t last{};
};

// The "serial" callback: one byte a command, 's' = start/stop.
void on_link(pv_board_app_t *app, int fd, short revents, void *) {
  if (!(revents & POLLIN)) return;
  char cmd[16];
  const ssize_t n = read(fd, cmd, sizeof cmd);
  for (ssize_t i = 0; i < n; ++i) {
    if (cmd[i] == 's') assert_int_equal(pv_board_app_post(app, PV_EV_START_STOP), PV_BOARD_APP_OK);
  }
}

void on_news(pv_board_app_t *app, pv_board_news_t what, const pv_board_model_t *m, void *user) {
  Link *link = static_cast<Link *>(user);
  if (what == PV_NEWS_STATE) {
    link->states.push_back(m->state);
    // The link starts a scan as soon as the board is ready.
    if (m->state == PV_BOARD_IDLE && link->results == 0) assert_int_equal(write(link->wr, "s", 1), 1);
  }
  if (what == PV_NEWS_ESTIMATE) link->estimates++;
  if (what == PV_NEWS_RESULT) {
    link->results++;
    link->last = *m;
    pv_board_app_quit(app);
  }
}

void link_drives_a_whole_scan(void **) {
  char err[512] = "";
  pv_emu_options_t eo;
  pv_emu_options_default(&eo);
  eo.interval_ms = 10;
  eo.bytes_per_interval = 8000;  // ~0.8 MB/s: a few live estimates
  pv_emu_t *emu = nullptr;
  if (pv_emu_create_from_file(&emu, g_frames, &eo, err, sizeof err) != 0) fail_msg("emulator: %s", err);

  char dir[] = "/tmp/pv_link_hookXXXXXX";
  assert_non_null(mkdtemp(dir));
  pv_board_config_t cfg;
  pv_board_config_default(&cfg);
  std::snprintf(cfg.display, sizeof cfg.display, "png:%s", dir);
  std::snprintf(cfg.input, sizeof cfg.input, "none");
  if (pv_board_app_init(&g_app, &cfg, err, sizeof err) != PV_BOARD_APP_OK) fail_msg("init: %s", err);

  Link link;
  int fds[2];
  assert_int_equal(pipe2(fds, O_NONBLOCK | O_CLOEXEC), 0);
  link.rd = fds[0];
  link.wr = fds[1];
  assert_int_equal(pv_board_app_watch(&g_app, link.rd, 0, on_link, nullptr), PV_BOARD_APP_OK);
  assert_int_equal(pv_board_app_watch_events(&g_app, link.rd, POLLIN), PV_BOARD_APP_OK);  // as a link would
  assert_int_equal(pv_board_app_watch_events(&g_app, 12345, POLLIN), PV_BOARD_APP_ERR_NOT_WATCHED);
  pv_board_app_set_observer(&g_app, on_news, &link);

  assert_int_equal(pv_board_app_run(&g_app, err, sizeof err), PV_BOARD_APP_OK);
  pv_board_app_close(&g_app);
  pv_emu_destroy(emu);
  close(fds[0]);
  close(fds[1]);
  std::system((std::string("rm -rf '") + dir + "'").c_str());

  assert_int_equal(link.results, 1);
  assert_int_equal(link.last.state, PV_BOARD_RESULT);
  assert_int_equal(link.last.result_status, PV_OK);
  assert_true(link.last.result.volume_cm3 > 0);
  assert_true(link.estimates >= 1);
  // The observer saw the whole story in order.
  const std::vector<pv_board_state_t> want = {PV_BOARD_IDLE, PV_BOARD_SCANNING,
                                              PV_BOARD_MEASURING, PV_BOARD_RESULT};
  assert_true(link.states == want);
}

}  // namespace

int main(int argc, char **argv) {
  if (!pv_emu_available()) {
    std::printf("SKIP: not running under umockdev-wrapper\n");
    return 77;
  }
  if (argc < 2) {
    std::fprintf(stderr, "usage: test_board_link_hook FILE.frames\n");
    return 2;
  }
  g_frames = argv[1];
  pv_board_block_signals();
  const struct CMUnitTest tests[] = {cmocka_unit_test(link_drives_a_whole_scan)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
