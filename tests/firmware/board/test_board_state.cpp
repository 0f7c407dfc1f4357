// The board's state machine (firmware/board_state.c), its configuration
// file parser and the coverage hint, without devices.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "pitvol/board_fonts.h"

extern "C" {
#include "board_config.h"
#include "board_app.h"
#include "board_link.h"
#include "board_screens.h"
#include "board_state.h"
#include "pitvol/advice.h"
#include "pitvol/config_fields.h"
}

#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

pv_board_model_t booted(bool present) {
  pv_board_model_t m;
  pv_board_init(&m);
  pv_board_step(&m, present ? PV_EV_SCANNER_ARRIVED : PV_EV_SCANNER_GONE);
  return m;
}

void boot_goes_to_idle_or_no_scanner(void **) {
  pv_board_model_t m = booted(true);
  assert_int_equal(m.state, PV_BOARD_IDLE);
  m = booted(false);
  assert_int_equal(m.state, PV_BOARD_NO_SCANNER);
}

void full_scan_cycle(void **) {
  pv_board_model_t m = booted(true);
  unsigned a = pv_board_step(&m, PV_EV_START_STOP);
  assert_int_equal(m.state, PV_BOARD_SCANNING);
  assert_true(a & PV_ACT_BEGIN_SCAN);
  a = pv_board_step(&m, PV_EV_TICK);
  assert_true(a & PV_ACT_ESTIMATE);
  a = pv_board_step(&m, PV_EV_START_STOP);
  assert_true(a & PV_ACT_STOP_SCAN);
  assert_int_equal(m.state, PV_BOARD_SCANNING);  // until the scanner ends it
  a = pv_board_step(&m, PV_EV_START_STOP);     // a second press does not stop twice
  assert_false(a & PV_ACT_STOP_SCAN);
  a = pv_board_step(&m, PV_EV_SCAN_ENDED);
  assert_int_equal(m.state, PV_BOARD_MEASURING);
  assert_true(a & PV_ACT_MEASURE);
  assert_int_equal(pv_board_step(&m, PV_EV_START_STOP), 0u);  // busy: buttons ignored
  m.result_status = PV_OK;
  pv_board_step(&m, PV_EV_MEASURED);
  assert_int_equal(m.state, PV_BOARD_RESULT);
  pv_board_step(&m, PV_EV_ENTER);
  assert_int_equal(m.state, PV_BOARD_IDLE);
  pv_board_step(&m, PV_EV_ENTER);  // the last result again
  assert_int_equal(m.state, PV_BOARD_RESULT);
}

void refused_result(void **) {
  pv_board_model_t m = booted(true);
  pv_board_step(&m, PV_EV_START_STOP);
  pv_board_step(&m, PV_EV_SCAN_ENDED);
  m.result_status = PV_ERR_WALL_GAP;
  pv_board_step(&m, PV_EV_MEASURED);
  assert_int_equal(m.state, PV_BOARD_REFUSED);
  assert_true(pv_board_step(&m, PV_EV_START_STOP) & PV_ACT_BEGIN_SCAN);  // rescan at once
}

void unplug_pauses_and_resumes(void **) {
  pv_board_model_t m = booted(true);
  pv_board_step(&m, PV_EV_START_STOP);
  pv_board_step(&m, PV_EV_SCANNER_GONE);
  assert_int_equal(m.state, PV_BOARD_PAUSED);
  unsigned a = pv_board_step(&m, PV_EV_SCANNER_ARRIVED);
  assert_int_equal(m.state, PV_BOARD_SCANNING);
  assert_false(a & PV_ACT_BEGIN_SCAN);  // same scan: the session is not reset
  assert_int_equal(m.board_warnings, 0u);
}

void unplug_then_stop_measures_with_warning(void **) {
  pv_board_model_t m = booted(true);
  pv_board_step(&m, PV_EV_START_STOP);
  pv_board_step(&m, PV_EV_SCANNER_GONE);
  const unsigned a = pv_board_step(&m, PV_EV_START_STOP);
  assert_int_equal(m.state, PV_BOARD_MEASURING);
  assert_true(a & PV_ACT_MEASURE);
  assert_true(m.board_warnings & PV_BOARD_WARN_ENDED_UNPLUGGED);
}

void stop_then_unplug_then_replug_measures(void **) {
  pv_board_model_t m = booted(true);
  pv_board_step(&m, PV_EV_START_STOP);
  pv_board_step(&m, PV_EV_START_STOP);  // stopping
  pv_board_step(&m, PV_EV_SCANNER_GONE);
  assert_int_equal(m.state, PV_BOARD_PAUSED);
  assert_true(pv_board_step(&m, PV_EV_SCANNER_ARRIVED) & PV_ACT_MEASURE);
  assert_true(m.board_warnings & PV_BOARD_WARN_ENDED_UNPLUGGED);
}

void armed_start_waits_for_scanner(void **) {
  pv_board_model_t m = booted(false);
  assert_int_equal(pv_board_step(&m, PV_EV_START_STOP) & PV_ACT_BEGIN_SCAN, 0u);
  assert_true(m.armed);
  assert_true(pv_board_step(&m, PV_EV_SCANNER_ARRIVED) & PV_ACT_BEGIN_SCAN);
  assert_int_equal(m.state, PV_BOARD_SCANNING);
  // Not armed: arrival only makes the board ready.
  m = booted(false);
  pv_board_step(&m, PV_EV_SCANNER_ARRIVED);
  assert_int_equal(m.state, PV_BOARD_IDLE);
}

void failed_start_returns_to_rest(void **) {
  pv_board_model_t m = booted(true);
  pv_board_step(&m, PV_EV_START_STOP);
  pv_board_step(&m, PV_EV_SCAN_FAILED);
  assert_int_equal(m.state, PV_BOARD_IDLE);
}

void config_file_parses_and_rejects(void **) {
  pv_board_config_t c;
  pv_board_config_default(&c);
  char err[256];
  const char *path = "test_board_config.conf";
  FILE *f = std::fopen(path, "w");
  assert_non_null(f);
  std::fputs("# board\nusb_vendor = 0x1234\ndisplay = png:out  # host\ndisplay_width = 480\n"
             "units = l\ncore.method = polar\ncore.layer_mm = 1.0\ncore.max_layers = 900\n", f);
  std::fclose(f);
  assert_int_equal(pv_board_config_load(&c, path, err, sizeof err), PV_BOARD_CONFIG_OK);
  assert_int_equal(c.usb_vendor, 0x1234);
  assert_string_equal(c.display, "png:out");
  assert_int_equal(c.display_width, 480);
  assert_int_equal(c.units, PV_UNITS_LITRE);
  assert_int_equal(c.core.method, PV_METHOD_POLAR);
  assert_true(c.core.layer_mm == 1.0f);
  assert_int_equal(c.core.max_layers, 900u);
  assert_int_equal(pv_board_config_check(&c, err, sizeof err), PV_BOARD_CONFIG_OK);

  f = std::fopen(path, "w");
  std::fputs("units = cm3\nbogus = 1\n", f);
  std::fclose(f);
  assert_int_equal(pv_board_config_load(&c, path, err, sizeof err), PV_BOARD_CONFIG_ERR_UNKNOWN_KEY);
  assert_non_null(std::strstr(err, ":2: unknown key 'bogus'"));
  assert_int_equal(pv_board_config_set(&c, "usb_product", "70000", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_int_equal(pv_board_config_set(&c, "core.knn_k", "-3", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_string_equal(err, "core.knn_k = -3 is outside the allowed 2 .. 32");
  assert_int_equal(pv_board_config_set(&c, "core.nope", "1", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_UNKNOWN_KEY);
  // A line without '=' and a file that is not there.
  f = std::fopen(path, "w");
  std::fputs("units = cm3\nunits cm3\n", f);
  std::fclose(f);
  assert_int_equal(pv_board_config_load(&c, path, err, sizeof err), PV_BOARD_CONFIG_ERR_SYNTAX);
  assert_non_null(std::strstr(err, ":2: expected 'key = value'"));
  assert_int_equal(pv_board_config_load(&c, "no-such-board.conf", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_OPEN);
  assert_non_null(std::strstr(err, "no-such-board.conf: cannot open the board configuration"));
  assert_non_null(std::strstr(pv_board_config_status_message(PV_BOARD_CONFIG_ERR_OPEN), "--config"));
  const std::string long_path(300, 'p');
  assert_int_equal(pv_board_config_set(&c, "display", long_path.c_str(), err, sizeof err),
                   PV_BOARD_CONFIG_ERR_TOO_LONG);
  // One line with the key, the value and the allowed range; a decimal
  // comma, hexadecimal and inf are refused, not read as other numbers.
  f = std::fopen(path, "w");
  std::fputs("units = cm3\n\ncore.layer_mm = 9\n", f);
  std::fclose(f);
  assert_int_equal(pv_board_config_load(&c, path, err, sizeof err), PV_BOARD_CONFIG_ERR_VALUE);
  assert_non_null(std::strstr(err, "test_board_config.conf:3: core.layer_mm = 9 is outside the allowed 0.1 .. 2"));
  assert_null(std::strchr(err, '\n'));
  assert_int_equal(pv_board_config_set(&c, "core.layer_mm", "0,5", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_non_null(std::strstr(err, "write decimals with a point"));
  assert_int_equal(pv_board_config_set(&c, "core.layer_mm", "0x1", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_int_equal(pv_board_config_set(&c, "core.max_unseen_share", "inf", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_int_equal(pv_board_config_set(&c, "core.knn_k", "8.5", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_non_null(std::strstr(err, "not a whole number (allowed: 2 .. 32)"));
  assert_int_equal(pv_board_config_set(&c, "units", "m3", err, sizeof err), PV_BOARD_CONFIG_ERR_VALUE);
  assert_string_equal(err, "units = m3 must be cm3 or l");
  c.core.layer_mm = 50.0f;  // out of the core's range
  assert_int_equal(pv_board_config_check(&c, err, sizeof err), PV_BOARD_CONFIG_ERR_CORE);
  assert_non_null(std::strstr(err, "core.layer_mm"));
  c.core.layer_mm = 1.0f;
  c.display_height = 200;
  assert_int_equal(pv_board_config_check(&c, err, sizeof err), PV_BOARD_CONFIG_ERR_DISPLAY_SIZE);
  std::remove(path);
}

void coverage_hint_names_the_widest_unseen_band(void **) {
  pv_result_t r{};
  r.depth_mm = 160;
  r.coverage_bands = PV_COVERAGE_BANDS;
  for (float &c : r.coverage) c = 0.9f;
  char l1[64], l2[64];
  assert_int_equal(pv_advice_live(&r, PV_OK, l1, sizeof l1, l2, sizeof l2), 0);
  r.coverage[1] = 0.2f;                     // 10-20 mm
  r.coverage[3] = r.coverage[4] = 0.1f;     // 30-50 mm: wider, wins
  assert_int_equal(pv_advice_live(&r, PV_OK, l1, sizeof l1, l2, sizeof l2), 1);
  assert_string_equal(l1, "wall 30-50 mm not seen");
  assert_string_equal(l2, "tilt into the pit");
  for (float &c : r.coverage) c = 0.9f;
  r.coverage[15] = 0.0f;  // under the rim
  pv_advice_live(&r, PV_OK, l1, sizeof l1, l2, sizeof l2);
  assert_string_equal(l1, "wall 150-160 mm not seen");
  assert_string_equal(l2, "aim at the upper wall");
  // Amber bands (seen, but under 80 %) are a hint too, not "wall seen: STOP".
  for (float &c : r.coverage) c = 0.9f;
  r.coverage[6] = r.coverage[7] = 0.6f;
  assert_int_equal(pv_advice_live(&r, PV_OK, l1, sizeof l1, l2, sizeof l2), 1);
  assert_string_equal(l1, "wall 60-80 mm thin");
  assert_string_equal(l2, "tilt into the pit");
  // The core's own gap wins when it refuses for it.
  r.gap_from_mm = 55;
  r.gap_to_mm = 90;
  pv_advice_live(&r, PV_ERR_WALL_GAP, l1, sizeof l1, l2, sizeof l2);
  assert_string_equal(l1, "wall 55-90 mm not seen");
}

// Every warning bit has its name, sentence and screen form in the core's
// one table; the screen form fits a 320-px line with its "! " or "note: ".
void warning_table_is_complete(void **) {
  for (uint32_t bit = 1; bit <= PV_WARN_ALL; bit <<= 1) {
    assert_non_null(pv_warning_name(bit));
    assert_non_null(pv_warning_message(bit));
    assert_non_null(pv_warning_short(bit));
    assert_true(std::strlen(pv_warning_short(bit)) <= 24);
  }
  assert_null(pv_warning_name(PV_WARN_ALL + 1));
  // Thinning is never a warning; a bridge is one from 1 % of the volume.
  assert_int_equal(pv_warnings_attention(PV_WARN_POINTS_THINNED, 0.5), 0u);
  assert_int_equal(pv_warnings_attention(PV_WARN_BRIDGED, 0.009), 0u);
  assert_int_equal(pv_warnings_attention(PV_WARN_BRIDGED, 0.01), PV_WARN_BRIDGED);
  assert_int_equal(pv_warnings_attention(PV_WARN_LARGE_TILT, 0), PV_WARN_LARGE_TILT);
}

// The table of settings agrees with pv_config_validate(): each field's
// ends are accepted, a step beyond each is refused, by the core itself.
void config_ranges_are_the_cores(void **) {
  for (size_t i = 0; i < pv_config_field_count; ++i) {
    const pv_config_field_t &f = pv_config_fields[i];
    for (int end = 0; end < 2; ++end) {
      for (int beyond = 0; beyond < 2; ++beyond) {
        pv_config_t cfg;
        pv_config_default(&cfg);
        double v = end ? f.max : f.min;
        const double step = f.is_float ? std::fmax(1e-3, std::fabs(v) * 1e-3) : 1.0;
        if (beyond) v += end ? step : -step;
        if (!f.is_float && v < 0) continue;  // an unsigned field has no value below 0
        char *base = reinterpret_cast<char *>(&cfg) + f.offset;
        if (f.is_float) {
          const float x = float(v);
          std::memcpy(base, &x, sizeof x);
        } else {
          const uint32_t x = uint32_t(v);
          std::memcpy(base, &x, sizeof x);
        }
        if (std::strcmp(f.name, "points_per_layer") == 0 || std::strcmp(f.name, "max_layers") == 0) {
          cfg.max_layers = std::strcmp(f.name, "max_layers") == 0 ? cfg.max_layers : 64;
          cfg.points_per_layer = std::strcmp(f.name, "points_per_layer") == 0 ? cfg.points_per_layer : 64;
        }
        const char *bad = nullptr;
        const bool ok = pv_config_validate(&cfg, &bad) == PV_OK;
        if (ok == bool(beyond)) {
          std::fprintf(stderr, "%s = %.9g: core says %s\n", f.name, v, ok ? "ok" : bad);
          fail();
        }
      }
    }
  }
}

// Draws a model's screen and returns the text it laid out.
std::string screen_text(const pv_board_model_t &m, pv_board_units_t units = PV_UNITS_CM3) {
  static pv_board_fonts_t fonts;
  static bool parsed = false;
  if (!parsed) {
    assert_int_equal(pv_font_parse_psf2(&fonts.body, pv_font_10x20, pv_font_10x20_bytes), PV_DISPLAY_OK);
    assert_int_equal(pv_font_parse_psf2(&fonts.big, pv_font_16x32, pv_font_16x32_bytes), PV_DISPLAY_OK);
    parsed = true;
  }
  std::vector<uint8_t> mem(pv_canvas_bytes(320, 240, 4096));
  pv_canvas_t c;
  assert_int_equal(pv_canvas_init(&c, 320, 240, 4096, mem.data(), mem.size()), PV_DISPLAY_OK);
  pv_board_draw(&c, &m, &fonts, units);
  assert_false(c.text_truncated);
  return c.text;
}

bool has(const std::string &text, const char *what) {
  if (text.find(what) != std::string::npos) return true;
  std::fprintf(stderr, "screen lacks '%s':\n%s", what, text.c_str());
  return false;
}

// A full event queue refuses the event, counts it, and the result and
// refusal screens say so (nothing is dropped unseen).
void full_queue_counts_and_shows_lost_events(void **) {
  static pv_board_app_t app;  // the queue only: no devices are opened
  std::memset(&app, 0, sizeof app);
  pv_board_init(&app.model);
  for (unsigned i = 0; i < PV_BOARD_EVENT_QUEUE; ++i)
    assert_int_equal(pv_board_app_post(&app, PV_EV_TICK), PV_BOARD_APP_OK);
  assert_int_equal(app.model.dropped_events, 0);
  assert_int_equal(pv_board_app_post(&app, PV_EV_SCAN_ENDED), PV_BOARD_APP_ERR_QUEUE_FULL);
  assert_int_equal(pv_board_app_post(&app, PV_EV_MEASURED), PV_BOARD_APP_ERR_QUEUE_FULL);
  assert_int_equal(app.model.dropped_events, 2);
  assert_int_equal(app.q_len, PV_BOARD_EVENT_QUEUE);

  pv_board_model_t m = booted(true);
  m.state = PV_BOARD_RESULT;
  m.result_status = PV_OK;
  m.result.volume_cm3 = 1000;
  assert_true(screen_text(m).find("events lost") == std::string::npos);
  m.dropped_events = app.model.dropped_events;
  assert_true(has(screen_text(m), "|! 2 board events lost\n"));
  m.state = PV_BOARD_REFUSED;
  m.result_status = PV_ERR_WALL_GAP;
  assert_true(has(screen_text(m), "|2 board events lost\n"));
}

void watch_nothing(pv_board_app_t *, int, short, void *) {}

// The watch table holds PV_BOARD_MAX_WATCHES descriptors; one more is
// refused and leaves the table as it was.
void full_watch_table_refuses(void **) {
  static pv_board_app_t app;  // the table only: no devices are opened
  std::memset(&app, 0, sizeof app);
  for (unsigned i = 0; i < PV_BOARD_MAX_WATCHES; ++i)
    assert_int_equal(pv_board_app_watch(&app, 10 + (int)i, POLLIN, watch_nothing, nullptr),
                     PV_BOARD_APP_OK);
  assert_int_equal(pv_board_app_watch(&app, 20, POLLIN, watch_nothing, nullptr),
                   PV_BOARD_APP_ERR_WATCHES_FULL);
  assert_int_equal(app.nwatches, PV_BOARD_MAX_WATCHES);
  for (size_t w = 0; w < app.nwatches; ++w) assert_int_not_equal(app.watches[w].fd, 20);

  std::memset(&app, 0, sizeof app);
  assert_int_equal(pv_board_app_watch(&app, -1, POLLIN, watch_nothing, nullptr),
                   PV_BOARD_APP_ERR_WATCH_ARGUMENT);
  assert_int_equal(pv_board_app_watch(&app, 10, POLLIN, nullptr, nullptr),
                   PV_BOARD_APP_ERR_WATCH_ARGUMENT);
  assert_int_equal(app.nwatches, 0);
  assert_int_equal(pv_board_app_watch(&app, 10, POLLIN, watch_nothing, nullptr), PV_BOARD_APP_OK);
  assert_int_equal(pv_board_app_watch_events(&app, 10, POLLIN | POLLOUT), PV_BOARD_APP_OK);
  assert_int_equal(app.watches[0].events, POLLIN | POLLOUT);
  assert_int_equal(pv_board_app_watch_events(&app, 11, POLLIN), PV_BOARD_APP_ERR_NOT_WATCHED);
  assert_int_equal(app.watches[0].events, POLLIN | POLLOUT);
}

// The start refuses what it cannot set up with the part that failed and
// the failing module's own name in the sentence.
void init_names_the_part_that_failed(void **) {
  static pv_board_app_t app;
  char err[512] = "";
  pv_board_config_t cfg;
  pv_board_config_default(&cfg);
  cfg.display_width = 0;  // outside its range: the configuration's check refuses it
  assert_int_equal(pv_board_app_init(&app, &cfg, err, sizeof err), PV_BOARD_APP_ERR_CONFIG);
  assert_non_null(std::strstr(err, "[PV_BOARD_CONFIG_ERR_"));
  pv_board_app_close(&app);

  pv_board_config_default(&cfg);
  std::snprintf(cfg.display, sizeof cfg.display, "png:/nonexistent-pitvol-dir/screens");
  err[0] = '\0';
  assert_int_equal(pv_board_app_init(&app, &cfg, err, sizeof err), PV_BOARD_APP_ERR_DISPLAY);
  assert_non_null(std::strstr(err, "[PV_DISPLAY_ERR_"));
  pv_board_app_close(&app);
}

// A result log that cannot be opened stops the link's start (the board
// does not run without keeping results unless told result_log = none).
void link_start_refuses_a_log_it_cannot_open(void **) {
  char file[] = "/tmp/pv_board_logXXXXXX";
  const int fd = mkstemp(file);
  assert_true(fd >= 0);
  close(fd);
  static pv_board_app_t app;
  std::memset(&app, 0, sizeof app);
  pv_board_config_default(&app.cfg);
  std::snprintf(app.cfg.result_log, sizeof app.cfg.result_log, "%s/log", file);  // under a file
  std::snprintf(app.cfg.serial, sizeof app.cfg.serial, "none");
  static pv_board_link_t bl;
  char err[512] = "";
  assert_int_equal(pv_board_link_start(&bl, &app, -1, err, sizeof err), PV_BOARD_LINK_ERR_LOG);
  assert_non_null(std::strstr(err, "cannot be opened"));
  unlink(file);

  // result_log = none and serial = none: a board without a link or a log.
  std::snprintf(app.cfg.result_log, sizeof app.cfg.result_log, "none");
  assert_int_equal(pv_board_link_start(&bl, &app, -1, err, sizeof err), PV_BOARD_LINK_OK);
  pv_board_link_stop(&bl);
}

// Each code has its own name and a message; an unknown one is named so.
void board_status_names(void **) {
  std::vector<std::string> names;
  for (int c = PV_STATUS_BASE_BOARD_APP + 1; c <= PV_BOARD_APP_ERR_POLL; ++c) {
    const auto st = static_cast<pv_board_app_status_t>(c);
    assert_non_null(std::strstr(pv_board_app_status_name(st), "PV_BOARD_APP_ERR_"));
    assert_string_not_equal(pv_board_app_status_name(st), "PV_BOARD_APP_ERR_UNKNOWN");
    assert_true(std::strlen(pv_board_app_status_message(st)) > 20);
    names.emplace_back(pv_board_app_status_name(st));
  }
  for (int c = PV_STATUS_BASE_BOARD_LINK + 1; c <= PV_BOARD_LINK_ERR_WATCH; ++c) {
    const auto st = static_cast<pv_board_link_status_t>(c);
    assert_string_not_equal(pv_board_link_status_name(st), "PV_BOARD_LINK_ERR_UNKNOWN");
    assert_true(std::strlen(pv_board_link_status_message(st)) > 20);
    names.emplace_back(pv_board_link_status_name(st));
  }
  for (size_t i = 0; i < names.size(); ++i)
    for (size_t j = i + 1; j < names.size(); ++j) assert_string_not_equal(names[i].c_str(), names[j].c_str());
  assert_string_equal(pv_board_app_status_name(static_cast<pv_board_app_status_t>(999)),
                      "PV_BOARD_APP_ERR_UNKNOWN");
  assert_string_equal(pv_board_link_status_name(static_cast<pv_board_link_status_t>(1020)),
                      "PV_BOARD_LINK_ERR_UNKNOWN");
}

void screens_say_what_matters(void **) {
  pv_board_model_t m = booted(true);
  m.state = PV_BOARD_RESULT;
  m.result_status = PV_OK;
  m.result.volume_cm3 = 11712.84;
  m.result.interval_cm3 = 12.34;
  m.result.depth_mm = 297.37;
  m.result.warnings = PV_WARN_BRIDGED | PV_WARN_POINTS_THINNED;
  m.result.unseen_share = 0.049;
  std::string t = screen_text(m);
  assert_true(has(t, "|11712.8\n"));
  assert_true(has(t, "|\xC2\xB1 12.3 cm\xC2\xB3\n"));
  assert_true(has(t, "|! unseen wall bridged\n"));
  assert_true(has(t, "|note: dense bins thinned\n"));
  // An ordinary scan: thinned by design and a short bridge (0.4 % of the
  // volume) are notes, not warnings; the title stays green.
  m.result.unseen_share = 0.004;
  t = screen_text(m);
  assert_true(has(t, "|no warnings\n"));
  assert_true(has(t, "|note: unseen wall bridged\n"));
  assert_true(t.find("|! ") == std::string::npos);
  assert_true(has(t, "result volume_cm3=11712.84 "));
  t = screen_text(m, PV_UNITS_LITRE);
  assert_true(has(t, "|11.713\n"));

  m.state = PV_BOARD_REFUSED;
  m.result_status = PV_ERR_WALL_GAP;
  m.result.gap_from_mm = 55;
  m.result.gap_to_mm = 90;
  m.result.depth_mm = 297;
  m.result.points_in = 150000;
  t = screen_text(m);
  assert_true(has(t, "|wall 55-90 mm not seen\n"));
  assert_true(has(t, "|rescan: tilt into the pit\n"));
  // The whole wall "unseen" on a 5,837-point scan: too few points, not a band.
  m.result.gap_from_mm = 0;
  m.result.gap_to_mm = 297;
  m.result.points_in = 5837;
  t = screen_text(m);
  assert_true(has(t, "|too few points (5 837)\n"));
  assert_true(has(t, "|rescan slowly, all round\n"));
  assert_true(t.find("tilt into") == std::string::npos);
  m.result.points_in = 150000;  // many points, but the gap is the whole wall
  assert_true(has(screen_text(m), "|too few points (150 000)\n"));
  assert_true(has(t, "refused status=PV_ERR_WALL_GAP"));
  assert_true(t.find("11712") == std::string::npos);  // a refusal shows no number

  // Not a pit: the screen says which check refused, with its figure, and
  // fits the line (screen_text fails on a truncated text).
  m.result_status = PV_ERR_NOT_A_PIT;
  m.result.failed_check = PV_PIT_CHECK_POINTS_INSIDE;
  m.result.check_value = 0.264;
  m.result.check_limit = 0.15;
  t = screen_text(m);
  assert_true(has(t, "|26% of points in the void\n"));
  m.result.failed_check = PV_PIT_CHECK_NARROW_MOUTH;
  m.result.check_value = 0.112;
  m.result.check_limit = 0.5;
  assert_true(has(screen_text(m), "|mouth 11% of widest part\n"));
  m.result.failed_check = PV_PIT_CHECK_TOO_WIDE;
  m.result.check_value = 318;
  m.result.check_limit = 315;
  assert_true(has(screen_text(m), "|wider than 630 mm\n"));
  m.result.failed_check = PV_PIT_CHECK_OPENING_TILT;
  t = screen_text(m);
  assert_true(has(t, "|opening faces away\n"));
  assert_true(has(t, "|rescan from above the pit\n"));
  m.result.failed_check = PV_PIT_CHECK_NO_POINTS;
  assert_true(has(screen_text(m), "|does not look like a pit\n"));
  // A scan that holds the pit twice: a rescan in one pass, not "alone".
  m.result.failed_check = PV_PIT_CHECK_DOUBLED_WALL;
  m.result.check_value = 0.75;
  m.result.check_limit = 0.2;
  t = screen_text(m);
  assert_true(has(t, "|wall seen twice\n"));
  assert_true(has(t, "|rescan in one steady pass\n"));
  m.result.failed_check = PV_PIT_CHECK_DOUBLED_FLOOR;
  m.result.check_value = 0.357;
  m.result.check_limit = 0.03;
  assert_true(has(screen_text(m), "|floor seen twice\n"));

  m.state = PV_BOARD_SCANNING;
  m.points = 123456;
  m.live_valid = 1;
  m.live_status = PV_OK;
  m.live.volume_cm3 = 9000;
  m.live.depth_mm = 160;
  m.live.coverage_bands = PV_COVERAGE_BANDS;
  for (float &c : m.live.coverage) c = 1.0f;
  m.live.coverage[2] = 0.1f;
  t = screen_text(m);
  assert_true(has(t, "|~9000.0 cm\xC2\xB3\n"));
  assert_true(has(t, "|points 123 456\n"));
  assert_true(has(t, "|wall 20-30 mm not seen\n"));
  assert_true(has(t, "coverage 1.00 1.00 0.10 1.00"));
  // Two amber bands: no STOP yet, the thin band named; all green: STOP.
  m.live.coverage[2] = 1.0f;
  m.live.coverage[9] = m.live.coverage[10] = 0.7f;
  t = screen_text(m);
  assert_true(has(t, "|wall 90-110 mm thin\n"));
  assert_true(t.find("wall seen: STOP") == std::string::npos);
  m.live.coverage[9] = m.live.coverage[10] = 0.95f;
  assert_true(has(screen_text(m), "|wall seen: STOP\n"));

  m.state = PV_BOARD_PAUSED;
  t = screen_text(m);
  assert_true(has(t, "|123 456 points kept\n"));
}

// The RESULT screen with a density: 3000 g of soil from a 1525 +/- 30 cm3
// pit at 12.5 % moisture, reference 1850 kg/m3. By hand: wet 3000/1525 =
// 1.967 g/cm3, dry 1.967/1.125 = 1.749, compaction 1748.6/1850 = 94.5 %,
// its range 3000/1555/1.125/18.5 = 92.7 .. 3000/1495/1.125/18.5 = 96.4.
// Every body-text line of a screen ends inside 320 px (a clipped range
// would hide its upper end).
bool body_lines_fit(const std::string &text) {
  pv_font_t body;
  assert_int_equal(pv_font_parse_psf2(&body, pv_font_10x20, pv_font_10x20_bytes), PV_DISPLAY_OK);
  size_t at = 0;
  bool ok = true;
  while (at < text.size()) {
    const size_t end = text.find('\n', at);
    const std::string ln = text.substr(at, end - at);
    at = end == std::string::npos ? text.size() : end + 1;
    int x = 0, y = 0, h = 0, used = 0;
    if (std::sscanf(ln.c_str(), "text %d %d %d|%n", &x, &y, &h, &used) != 3 || h != 20 || used == 0) continue;
    const int w = pv_text_width(&body, 1, ln.c_str() + used);
    if (x + w > 320) {
      std::fprintf(stderr, "clipped: %s (%d px)\n", ln.c_str(), x + w);
      ok = false;
    }
  }
  return ok;
}

void result_screen_shows_density(void **) {
  pv_board_model_t m = booted(true);
  m.state = PV_BOARD_RESULT;
  m.result_status = PV_OK;
  m.result.volume_cm3 = 1525;
  m.result.interval_cm3 = 30;
  m.result.depth_mm = 150;
  m.result.warnings = PV_WARN_BRIDGED;
  m.result.unseen_share = 0.05;
  pv_density_input_t in{};
  in.volume_cm3 = 1525;
  in.interval_cm3 = 30;
  in.has_mass = 1;
  in.mass_g = 3000;
  in.has_moisture = 1;
  in.moisture_percent = 12.5;
  in.reference_max_dry_kg_m3 = 1850;
  assert_int_equal(pv_density_compute(&in, &m.density), PV_DENSITY_OK);
  std::string t = screen_text(m);
  assert_true(has(t, "|1525.0 \xC2\xB1 30.0 cm\xC2\xB3\n"));
  assert_true(has(t, "|wet 1.967 dry 1.749 g/cm\xC2\xB3\n"));
  assert_true(has(t, "|compaction 94.5% (92.7-96.4)\n"));
  assert_true(has(t, "|! unseen wall bridged\n"));  // the flags still fit
  assert_true(has(t, "density flags=0x7 "));
  assert_true(body_lines_fit(t));
  // The widest compaction line, over 100 % with a range: 3200/1525/1.125/18.5
  // = 100.8 %, 3200/1555/... = 98.9, 3200/1495/... = 102.8.
  in.mass_g = 3200;
  assert_int_equal(pv_density_compute(&in, &m.density), PV_DENSITY_OK);
  t = screen_text(m);
  assert_true(has(t, "|compaction 100.8% (98.9-102.8)\n"));
  assert_true(body_lines_fit(t));
  // No moisture: the wet density only.
  in.mass_g = 3000;
  in.has_moisture = 0;
  in.reference_max_dry_kg_m3 = 0;
  assert_int_equal(pv_density_compute(&in, &m.density), PV_DENSITY_OK);
  t = screen_text(m);
  assert_true(has(t, "|wet 1.967 g/cm\xC2\xB3 (no moisture)\n"));
  assert_true(t.find("|compaction") == std::string::npos);
  // No mass: the screen as before.
  m.density = pv_density_t{};
  t = screen_text(m);
  assert_true(has(t, "|1525.0\n"));
  assert_true(t.find("wet ") == std::string::npos);
}

void link_config_keys(void **) {
  pv_board_config_t c;
  pv_board_config_default(&c);
  char err[256];
  assert_string_equal(c.serial, "none");
  assert_string_equal(c.result_log, "none");
  assert_int_equal(c.serial_baud, 115200u);
  assert_int_equal(pv_board_config_set(&c, "serial_baud", "57600", err, sizeof err), PV_BOARD_CONFIG_OK);
  assert_int_equal(c.serial_baud, 57600u);
  assert_int_equal(pv_board_config_set(&c, "serial_baud", "12345", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_int_equal(pv_board_config_set(&c, "result_log", "/var/lib/pitvol", err, sizeof err), PV_BOARD_CONFIG_OK);
  assert_string_equal(c.result_log, "/var/lib/pitvol");
  assert_int_equal(pv_board_config_set(&c, "max_dry_density_kg_m3", "1850", err, sizeof err), PV_BOARD_CONFIG_OK);
  assert_true(c.max_dry_density_kg_m3 == 1850.0);
  assert_int_equal(pv_board_config_set(&c, "max_dry_density_kg_m3", "0", err, sizeof err), PV_BOARD_CONFIG_OK);
  assert_int_equal(pv_board_config_set(&c, "max_dry_density_kg_m3", "185", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_non_null(std::strstr(err, "1000 .. 2800 kg/m3"));
  assert_int_equal(pv_board_config_set(&c, "max_dry_density_kg_m3", "1,85", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_int_equal(pv_board_config_set(&c, "max_dry_density_kg_m3", "0x700", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_int_equal(pv_board_config_set(&c, "device_id", "PV-0001", err, sizeof err), PV_BOARD_CONFIG_OK);
  assert_int_equal(pv_board_config_set(&c, "device_id", "a-device-id-of-thirty-characters", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_TOO_LONG);
  assert_int_equal(pv_board_config_set(&c, "device_id", "PV\x1b[2J", err, sizeof err),
                   PV_BOARD_CONFIG_ERR_VALUE);
  assert_non_null(std::strstr(err, "control character"));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(boot_goes_to_idle_or_no_scanner),
      cmocka_unit_test(full_scan_cycle),
      cmocka_unit_test(refused_result),
      cmocka_unit_test(unplug_pauses_and_resumes),
      cmocka_unit_test(unplug_then_stop_measures_with_warning),
      cmocka_unit_test(stop_then_unplug_then_replug_measures),
      cmocka_unit_test(armed_start_waits_for_scanner),
      cmocka_unit_test(failed_start_returns_to_rest),
      cmocka_unit_test(config_file_parses_and_rejects),
      cmocka_unit_test(coverage_hint_names_the_widest_unseen_band),
      cmocka_unit_test(warning_table_is_complete),
      cmocka_unit_test(config_ranges_are_the_cores),
      cmocka_unit_test(screens_say_what_matters),
      cmocka_unit_test(full_queue_counts_and_shows_lost_events),
      cmocka_unit_test(full_watch_table_refuses),
      cmocka_unit_test(init_names_the_part_that_failed),
      cmocka_unit_test(link_start_refuses_a_log_it_cannot_open),
      cmocka_unit_test(board_status_names),
      cmocka_unit_test(result_screen_shows_density),
      cmocka_unit_test(link_config_keys),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
