/* The board's serial link and result log (board_link.h): the board
 * application as the link server's application. */
#include "board_link.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "pitvol/density.h"
#include "pitvol/link_result.h"

_Static_assert(PV_COVERAGE_BANDS <= sizeof(((pitvol_Status *)0)->coverage) / sizeof(float),
               "Status.coverage holds every band");

static long write_port(void *ctx, const uint8_t *data, size_t len) {
  pv_board_link_t *bl = (pv_board_link_t *)ctx;
  size_t w = 0;
  const pv_serial_status_t st = pv_serial_write(&bl->port, data, len, &w);
  if (st != PV_SERIAL_OK) {
    if (!bl->write_failed) printf("pitvol-board: serial: %s\n", pv_serial_status_message(st));
    bl->write_failed = 1;
    return -1;
  }
  return (long)w;
}

static pitvol_DeviceState device_state(pv_board_state_t s) {
  switch (s) {
    case PV_BOARD_SCANNING:
    case PV_BOARD_PAUSED: return pitvol_DeviceState_STATE_SCANNING;
    case PV_BOARD_MEASURING: return pitvol_DeviceState_STATE_COMPUTING;
    case PV_BOARD_RESULT:
    case PV_BOARD_REFUSED: return pitvol_DeviceState_STATE_RESULT;
    default: return pitvol_DeviceState_STATE_IDLE;
  }
}

/* The server's application: the board's model and configuration. */

static void app_status(void *ctx, pitvol_Status *s) {
  const pv_board_link_t *bl = (const pv_board_link_t *)ctx;
  const pv_board_model_t *md = &bl->app->model;
  s->state = device_state(md->state);
  s->points = md->points;
  const int scanning = md->state == PV_BOARD_SCANNING || md->state == PV_BOARD_PAUSED;
  if (scanning && md->live_valid) {
    if (md->live_status == PV_OK) {
      s->running_volume_cm3 = md->live.volume_cm3;
      s->running_interval_cm3 = md->live.interval_cm3;
    }
    const uint32_t n = md->live.coverage_bands <= PV_COVERAGE_BANDS ? md->live.coverage_bands : 0;
    for (uint32_t b = 0; b < n; ++b) s->coverage[b] = md->live.coverage[b];
    s->coverage_count = (pb_size_t)n;
  }
  s->mass_set = md->mass_set != 0;
  s->mass_g = md->mass_set ? md->mass_g : 0;
  s->moisture_set = md->moisture_set != 0;
  s->moisture_percent = md->moisture_set ? md->moisture_percent : 0;
}

static pitvol_NackCode post_or_busy(pv_board_link_t *bl, pv_board_event_t ev, char *why,
                                    size_t cap) {
  const pv_board_app_status_t st = pv_board_app_post(bl->app, ev);
  if (st != PV_BOARD_APP_OK) { /* PV_BOARD_APP_ERR_QUEUE_FULL: counted and shown by the board */
    snprintf(why, cap, "the board is busy; send the command again [%s]",
             pv_board_app_status_name(st));
    return pitvol_NackCode_NACK_BUSY;
  }
  return pitvol_NackCode_NACK_NONE;
}

/* The START button's event, where the button would start a scan. */
static pitvol_NackCode app_start_scan(void *ctx, char *why, size_t cap) {
  pv_board_link_t *bl = (pv_board_link_t *)ctx;
  const pv_board_model_t *m = &bl->app->model;
  if (m->state == PV_BOARD_IDLE || m->state == PV_BOARD_RESULT || m->state == PV_BOARD_REFUSED ||
      (m->state == PV_BOARD_NO_SCANNER && !m->armed)) {
    return post_or_busy(bl, PV_EV_START_STOP, why, cap);
  }
  snprintf(why, cap, "%s",
           m->state == PV_BOARD_NO_SCANNER ? "a scan already waits for the scanner; plug it in"
                                           : "a scan is already running; stop it first");
  return pitvol_NackCode_NACK_WRONG_STATE;
}

static pitvol_NackCode app_stop_scan(void *ctx, char *why, size_t cap) {
  pv_board_link_t *bl = (pv_board_link_t *)ctx;
  const pv_board_model_t *m = &bl->app->model;
  if ((m->state == PV_BOARD_SCANNING && !m->stopping) || m->state == PV_BOARD_PAUSED) {
    return post_or_busy(bl, PV_EV_START_STOP, why, cap);
  }
  if (m->state == PV_BOARD_NO_SCANNER && m->armed) {
    return post_or_busy(bl, PV_EV_BACK, why, cap); /* the waiting scan is called off */
  }
  snprintf(why, cap, "no scan is running; start one first");
  return pitvol_NackCode_NACK_WRONG_STATE;
}

static void app_set_density_input(void *ctx, pv_input_kind_t kind, double v) {
  pv_board_model_t *m = &((pv_board_link_t *)ctx)->app->model;
  if (kind == PV_INPUT_MOISTURE_PERCENT) {
    m->moisture_set = 1;
    m->moisture_percent = v;
    printf("pitvol-board: link: moisture %.17g %%\n", v);
  } else {
    m->mass_set = 1;
    m->mass_g = v;
    printf("pitvol-board: link: mass %.17g g\n", v);
  }
}

/* The record: the test id in the model, the rest in the configuration. */
static void app_get_record(void *ctx, pv_link_record_t *rec) {
  const pv_board_app_t *app = ((const pv_board_link_t *)ctx)->app;
  snprintf(rec->test_id, sizeof rec->test_id, "%s", app->model.test_id);
  snprintf(rec->location, sizeof rec->location, "%s", app->cfg.location);
  snprintf(rec->operator_name, sizeof rec->operator_name, "%s", app->cfg.operator_name);
  rec->max_dry_density_kg_m3 = app->cfg.max_dry_density_kg_m3;
  rec->required_compaction_percent = app->cfg.required_compaction_percent;
}

static void app_set_record(void *ctx, const pv_link_record_t *rec) {
  pv_board_app_t *app = ((pv_board_link_t *)ctx)->app;
  snprintf(app->model.test_id, sizeof app->model.test_id, "%s", rec->test_id);
  snprintf(app->cfg.location, sizeof app->cfg.location, "%s", rec->location);
  snprintf(app->cfg.operator_name, sizeof app->cfg.operator_name, "%s", rec->operator_name);
  app->cfg.max_dry_density_kg_m3 = rec->max_dry_density_kg_m3;
  app->cfg.required_compaction_percent = rec->required_compaction_percent;
  printf("pitvol-board: link: record test_id=%s location=%s operator=%s max_dry=%.17g required=%.17g\n",
         rec->test_id, rec->location, rec->operator_name, rec->max_dry_density_kg_m3,
         rec->required_compaction_percent);
}

static void app_note(void *ctx, const char *line) {
  (void)ctx;
  printf("pitvol-board: %s\n", line);
}

static const pv_link_app_t board_app_hooks = {
    app_status,     app_start_scan, app_stop_scan, app_set_density_input,
    app_get_record, app_set_record, app_note};

/* Queued frames out as far as the port takes them; poll for POLLOUT while
 * any remain. */
static void service(pv_board_link_t *bl) {
  if (!bl->have_port) return;
  const pv_link_status_t st = pv_link_server_service(&bl->srv, write_port, bl);
  (void)st; /* write_port said it in the board's log */
  const pv_board_app_status_t wst = pv_board_app_watch_events(
      bl->app, pv_serial_fd(&bl->port),
      (short)(POLLIN | (pv_link_tx_pending(&bl->srv.link) ? POLLOUT : 0)));
  if (wst != PV_BOARD_APP_OK) {
    fprintf(stderr, "pitvol-board: link: the port is not watched; nothing will be sent [%s]\n",
            pv_board_app_status_name(wst));
  }
}

static void on_port(pv_board_app_t *app, int fd, short revents, void *user) {
  (void)app;
  (void)fd;
  pv_board_link_t *bl = (pv_board_link_t *)user;
  if (revents & (POLLIN | POLLHUP | POLLERR)) {
    uint8_t buf[512];
    size_t n = 0;
    const pv_serial_status_t st = pv_serial_read(&bl->port, buf, sizeof buf, &n);
    if (st == PV_SERIAL_OK) pv_link_server_feed(&bl->srv, buf, n);
  }
  service(bl);
}

static void on_timer(pv_board_app_t *app, int fd, short revents, void *user) {
  (void)app;
  (void)revents;
  pv_board_link_t *bl = (pv_board_link_t *)user;
  uint64_t expirations = 0;
  if (read(fd, &expirations, sizeof expirations) <= 0) return;
  const pv_board_state_t s = bl->app->model.state;
  bl->ticks++;
  if (s == PV_BOARD_SCANNING || s == PV_BOARD_PAUSED || bl->ticks % 4u == 0) {
    pv_link_server_send_status(&bl->srv);
  }
  service(bl);
}

/* The result: into the log (durable), then out; its id is the record number. */
static void on_result(pv_board_link_t *bl) {
  pv_board_model_t *md = &bl->app->model;
  /* The record the result was taken under (its test id was used up by it). */
  pv_link_record_t rec;
  memset(&rec, 0, sizeof rec);
  app_get_record(bl, &rec);
  snprintf(rec.test_id, sizeof rec.test_id, "%s", md->result_test_id);
  const pv_link_result_source_t src = {md->result_status,
                                       &md->result,
                                       pv_method_name(bl->app->cfg.core.method),
                                       (int64_t)time(NULL),
                                       &md->density,
                                       md->mass_g,
                                       md->moisture_percent,
                                       &rec};
  pitvol_Result r;
  pv_link_result_message(&r, &src);
  const pv_log_status_t st = pv_link_server_log_result(&bl->srv, &r);
  if (st == PV_LOG_OK && r.id != 0) {
    md->result_id = r.id;
    printf("pitvol-board: logged result id=%u\n", r.id);
  } else if (st != PV_LOG_OK) {
    printf("pitvol-board: result not logged: %s\n", pv_log_status_message(st));
  }
  if (bl->have_port) pv_link_server_send_result(&bl->srv, &r, st);
}

static void on_news(pv_board_app_t *app, pv_board_news_t what, const pv_board_model_t *m, void *user) {
  (void)app;
  pv_board_link_t *bl = (pv_board_link_t *)user;
  if (what == PV_NEWS_RESULT) {
    on_result(bl);
  } else if (what == PV_NEWS_ESTIMATE && bl->have_port) {
    pv_link_server_send_status(&bl->srv); /* the running volume as soon as it is known */
  } else if (what == PV_NEWS_STATE && bl->have_port && m->state != PV_BOARD_RESULT &&
             m->state != PV_BOARD_REFUSED) {
    pv_link_server_send_status(&bl->srv); /* (a new result's Status follows the Result, with its id) */
  }
  service(bl);
}

_Static_assert(PV_BOARD_LINK_ERR_LOG > PV_STATUS_BASE_BOARD_LINK &&
                   PV_BOARD_LINK_ERR_WATCH < PV_STATUS_BASE_BOARD_LINK + PV_STATUS_RANGE / 2,
               "pv_board_link_status_t in its range (pitvol/status_codes.h)");

const char *pv_board_link_status_name(pv_board_link_status_t status) {
  switch (status) {
    case PV_BOARD_LINK_OK: return "PV_BOARD_LINK_OK";
    case PV_BOARD_LINK_ERR_LOG: return "PV_BOARD_LINK_ERR_LOG";
    case PV_BOARD_LINK_ERR_TIMER: return "PV_BOARD_LINK_ERR_TIMER";
    case PV_BOARD_LINK_ERR_WATCH: return "PV_BOARD_LINK_ERR_WATCH";
  }
  return "PV_BOARD_LINK_ERR_UNKNOWN";
}

const char *pv_board_link_status_message(pv_board_link_status_t status) {
  switch (status) {
    case PV_BOARD_LINK_OK: return "started";
    case PV_BOARD_LINK_ERR_LOG:
      return "the result log cannot be opened; check result_log in the configuration and the "
             "storage card, or set result_log = none to run without keeping results";
    case PV_BOARD_LINK_ERR_TIMER:
      return "the link's status timer cannot be set up; free descriptors";
    case PV_BOARD_LINK_ERR_WATCH:
      return "the board's loop takes no more descriptors for the link; a build with too few "
             "PV_BOARD_MAX_WATCHES";
  }
  return "unknown board link status";
}

pv_board_link_status_t pv_board_link_start(pv_board_link_t *bl, pv_board_app_t *app,
                                           int adopt_fd, char *err, size_t errcap) {
  memset(bl, 0, sizeof *bl);
  bl->app = app;
  bl->port.fd = -1;
  bl->timer_fd = -1;
  const pv_board_config_t *cfg = &app->cfg;
  if (strcmp(cfg->result_log, "none") != 0) {
    pv_log_config_t lc;
    pv_log_config_default(&lc);
    const pv_log_status_t st = pv_log_open(&bl->log, cfg->result_log, &lc);
    if (st != PV_LOG_OK) {
      /* At start the log's own sentence (about a result on screen) does not fit. */
      snprintf(err, errcap,
               "result log %s cannot be opened (%s: %s); check result_log in the configuration "
               "and the storage card, or set result_log = none to run without keeping results",
               cfg->result_log, pv_log_status_name(st),
               st == PV_LOG_ERR_IO ? strerror(bl->log.last_errno) : "invalid path or settings");
      return PV_BOARD_LINK_ERR_LOG;
    }
    bl->have_log = 1;
    const pv_log_recovery_t *rec = &bl->log.recovery;
    printf("pitvol-board: result log %s: results %u..%u, %u segments, %u torn bytes dropped\n",
           cfg->result_log, pv_log_first_seq(&bl->log), pv_log_last_seq(&bl->log), rec->segments,
           rec->torn_bytes);
  } else {
    printf("pitvol-board: no result log (result_log = none): results are not kept\n");
  }
  /* The server logs results with or without a port. */
  const pv_link_server_config_t sc = {&board_app_hooks, bl, bl->have_log ? &bl->log : NULL,
                                      cfg->device_id,
                                      pitvol_Capability_CAP_DENSITY | pitvol_Capability_CAP_LIVE_ESTIMATE,
                                      (uint32_t)time(NULL)};
  pv_link_server_init(&bl->srv, &sc);
  pv_board_app_set_observer(app, on_news, bl);
  pv_serial_status_t sst = PV_SERIAL_ERR_OPEN;
  if (adopt_fd >= 0) {
    sst = pv_serial_adopt(&bl->port, adopt_fd, cfg->serial_baud);
  } else if (strcmp(cfg->serial, "none") != 0) {
    sst = pv_serial_open(&bl->port, cfg->serial, cfg->serial_baud);
  } else {
    printf("pitvol-board: serial link off (serial = none)\n");
    return PV_BOARD_LINK_OK;
  }
  if (sst != PV_SERIAL_OK) {
    /* The board still measures and logs; the link is what is missing. */
    printf("pitvol-board: serial link off: %s: %s\n", adopt_fd >= 0 ? "pty" : cfg->serial,
           pv_serial_status_message(sst));
    return PV_BOARD_LINK_OK;
  }
  bl->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  struct itimerspec its;
  memset(&its, 0, sizeof its);
  its.it_interval.tv_nsec = (long)PV_BOARD_LINK_STATUS_MS * 1000000L;
  its.it_value = its.it_interval;
  if (bl->timer_fd < 0 || timerfd_settime(bl->timer_fd, 0, &its, NULL) != 0) {
    snprintf(err, errcap, "serial link: cannot set up its status timer (%s) [%s]", strerror(errno),
             pv_board_link_status_name(PV_BOARD_LINK_ERR_TIMER));
    return PV_BOARD_LINK_ERR_TIMER;
  }
  pv_board_app_status_t wst = pv_board_app_watch(app, pv_serial_fd(&bl->port), POLLIN, on_port, bl);
  if (wst == PV_BOARD_APP_OK) wst = pv_board_app_watch(app, bl->timer_fd, POLLIN, on_timer, bl);
  if (wst != PV_BOARD_APP_OK) {
    snprintf(err, errcap, "serial link: %s [%s]", pv_board_app_status_message(wst),
             pv_board_app_status_name(wst));
    return PV_BOARD_LINK_ERR_WATCH;
  }
  bl->have_port = 1;
  printf("pitvol-board: serial link on %s at %u baud\n", adopt_fd >= 0 ? "pty" : cfg->serial,
         cfg->serial_baud);
  pv_link_server_send_status(&bl->srv);
  service(bl);
  return PV_BOARD_LINK_OK;
}

void pv_board_link_stop(pv_board_link_t *bl) {
  if (bl->app == NULL) return; /* never started */
  if (bl->have_port) {
    if (pv_link_tx_flush(&bl->srv.link, write_port, bl) != PV_LINK_OK) {
      printf("pitvol-board: link: writing the port failed: %u frames not sent\n",
             bl->srv.link.tx_count);
    }
    const pv_link_stats_t *s = &bl->srv.link.stats;
    printf("pitvol-board: link: %u frames sent, %u received, %u corrupt, %u missed, %u repeated "
           "commands, %u status dropped, %u outbox dropped, %u host restarts\n",
           s->frames_sent, s->frames_received, s->frames_corrupt, s->frames_missed,
           s->commands_duplicate, s->lossy_dropped, bl->srv.out_dropped, s->peer_restarts);
    pv_serial_close(&bl->port);
  }
  bl->app->observer = NULL;
  if (bl->timer_fd >= 0) close(bl->timer_fd);
  if (bl->have_log) pv_log_close(&bl->log);
  bl->have_port = bl->have_log = 0;
  bl->timer_fd = -1;
}
