/*
 * The board application's resources and event loop (board_app.h).
 */
#include "board_app.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "board_alloc_zone.h"
#include "pitvol/board_fonts.h"

_Static_assert(PV_BOARD_APP_ERR_QUEUE_FULL > PV_STATUS_BASE_BOARD_APP &&
                   PV_BOARD_APP_ERR_POLL < PV_STATUS_BASE_BOARD_APP + PV_STATUS_RANGE / 2,
               "pv_board_app_status_t in its range (pitvol/status_codes.h)");

_Thread_local int pv_alloc_zone = PV_ZONE_NONE;

const char *pv_board_app_status_name(pv_board_app_status_t status) {
  switch (status) {
    case PV_BOARD_APP_OK: return "PV_BOARD_APP_OK";
    case PV_BOARD_APP_ERR_QUEUE_FULL: return "PV_BOARD_APP_ERR_QUEUE_FULL";
    case PV_BOARD_APP_ERR_WATCHES_FULL: return "PV_BOARD_APP_ERR_WATCHES_FULL";
    case PV_BOARD_APP_ERR_WATCH_ARGUMENT: return "PV_BOARD_APP_ERR_WATCH_ARGUMENT";
    case PV_BOARD_APP_ERR_NOT_WATCHED: return "PV_BOARD_APP_ERR_NOT_WATCHED";
    case PV_BOARD_APP_ERR_CONFIG: return "PV_BOARD_APP_ERR_CONFIG";
    case PV_BOARD_APP_ERR_DISPLAY: return "PV_BOARD_APP_ERR_DISPLAY";
    case PV_BOARD_APP_ERR_CORE: return "PV_BOARD_APP_ERR_CORE";
    case PV_BOARD_APP_ERR_INPUT: return "PV_BOARD_APP_ERR_INPUT";
    case PV_BOARD_APP_ERR_TIMER: return "PV_BOARD_APP_ERR_TIMER";
    case PV_BOARD_APP_ERR_SIGNAL: return "PV_BOARD_APP_ERR_SIGNAL";
    case PV_BOARD_APP_ERR_USB: return "PV_BOARD_APP_ERR_USB";
    case PV_BOARD_APP_ERR_POLL: return "PV_BOARD_APP_ERR_POLL";
  }
  return "PV_BOARD_APP_ERR_UNKNOWN";
}

const char *pv_board_app_status_message(pv_board_app_status_t status) {
  switch (status) {
    case PV_BOARD_APP_OK: return "running";
    case PV_BOARD_APP_ERR_QUEUE_FULL:
      return "the board's event queue is full and the event was dropped (counted on the result "
             "screen); send the command again";
    case PV_BOARD_APP_ERR_WATCHES_FULL:
      return "the board watches no more descriptors; a caller bug (raise PV_BOARD_MAX_WATCHES)";
    case PV_BOARD_APP_ERR_WATCH_ARGUMENT:
      return "a watch needs a descriptor and a callback; a caller bug";
    case PV_BOARD_APP_ERR_NOT_WATCHED: return "that descriptor is not watched; a caller bug";
    case PV_BOARD_APP_ERR_CONFIG: return "the board's configuration is refused; fix board.conf";
    case PV_BOARD_APP_ERR_DISPLAY:
      return "the display cannot be set up; check the display config and permissions";
    case PV_BOARD_APP_ERR_CORE:
      return "the core cannot be set up in its block; lower core.max_layers or "
             "core.points_per_layer";
    case PV_BOARD_APP_ERR_INPUT:
      return "the buttons cannot be opened; check the input config and permissions";
    case PV_BOARD_APP_ERR_TIMER:
      return "the live estimate's timer cannot be set up; free descriptors";
    case PV_BOARD_APP_ERR_SIGNAL:
      return "SIGTERM and SIGINT cannot be taken by the loop; free descriptors";
    case PV_BOARD_APP_ERR_USB:
      return "the scanner's USB driver cannot start; check libusb and the udev rules";
    case PV_BOARD_APP_ERR_POLL:
      return "the event loop cannot wait for its devices; the board stops (systemd restarts it)";
  }
  return "unknown board application status";
}

static uint64_t now_ms(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

static void notify(pv_board_app_t *app, pv_board_news_t what) {
  if (app->observer != NULL) app->observer(app, what, &app->model, app->observer_user);
}

/* Every accepted USB frame's points go straight into the core. */
static void on_points(void *user, const pv_usb_frame_header_t *h, const pv_point_t *pts, size_t n) {
  (void)h;
  pv_board_app_t *app = (pv_board_app_t *)user;
  const pv_board_state_t st = app->model.state;
  if (st != PV_BOARD_SCANNING && st != PV_BOARD_PAUSED) return; /* not in a scan */
  const int old = pv_alloc_zone_enter(PV_ZONE_PUSH);
  if (pv_session_push(app->session, pts, n) == PV_OK) app->model.points += n;
  pv_alloc_zone_enter(old);
}

pv_board_app_status_t pv_board_app_post(pv_board_app_t *app, pv_board_event_t ev) {
  if (app->q_len == PV_BOARD_EVENT_QUEUE) {
    /* Counted and shown: a lost SCAN_ENDED or MEASURED would otherwise
     * leave the screen waiting with nothing said. */
    app->model.dropped_events++;
    app->dirty = 1;
    fprintf(stderr, "pitvol-board: event queue full: %s dropped (%u so far)\n",
            pv_board_event_name(ev), (unsigned)app->model.dropped_events);
    return PV_BOARD_APP_ERR_QUEUE_FULL;
  }
  app->queue[(app->q_head + app->q_len) % PV_BOARD_EVENT_QUEUE] = ev;
  app->q_len++;
  return PV_BOARD_APP_OK;
}

/* The loop's own events: a full queue is counted, logged and shown by
 * pv_board_app_post; there is no one else to tell. */
static void post(pv_board_app_t *app, pv_board_event_t ev) {
  const pv_board_app_status_t full = pv_board_app_post(app, ev);
  (void)full;
}

pv_board_app_status_t pv_board_app_watch(pv_board_app_t *app, int fd, short events,
                                         pv_board_watch_fn fn, void *user) {
  if (fd < 0 || fn == NULL) return PV_BOARD_APP_ERR_WATCH_ARGUMENT;
  if (app->nwatches == PV_BOARD_MAX_WATCHES) return PV_BOARD_APP_ERR_WATCHES_FULL;
  app->watches[app->nwatches].fd = fd;
  app->watches[app->nwatches].events = events;
  app->watches[app->nwatches].fn = fn;
  app->watches[app->nwatches].user = user;
  app->nwatches++;
  return PV_BOARD_APP_OK;
}

pv_board_app_status_t pv_board_app_watch_events(pv_board_app_t *app, int fd, short events) {
  for (size_t w = 0; w < app->nwatches; ++w) {
    if (app->watches[w].fd == fd) {
      app->watches[w].events = events;
      return PV_BOARD_APP_OK;
    }
  }
  return PV_BOARD_APP_ERR_NOT_WATCHED;
}

void pv_board_app_set_observer(pv_board_app_t *app, pv_board_observer_fn fn, void *user) {
  app->observer = fn;
  app->observer_user = user;
}

void pv_board_app_quit(pv_board_app_t *app) { app->quit = 1; }

static void present(pv_board_app_t *app) {
  pv_board_draw(&app->canvas, &app->model, &app->fonts, app->cfg.units);
  char err[256];
  const pv_display_status_t st = pv_display_present(
      app->display, &app->canvas, pv_board_state_name(app->model.state), err, sizeof err);
  /* The board keeps running on a display that failed once: the scan and
   * the link do not need it, and the next screen may well get through. */
  if (st != PV_DISPLAY_OK) {
    fprintf(stderr, "pitvol-board: display: %s [%s]\n", err, pv_display_status_name(st));
  }
  app->presents++;
  /* After the screen is out: a watcher waiting for this line can read it. */
  if (app->presents == 1 || app->model.state != app->last_shown) {
    app->last_shown = app->model.state;
    printf("pitvol-board: screen %s\n", pv_board_state_name(app->model.state));
  }
}

static void log_result(const pv_board_app_t *app) {
  const pv_result_t *r = &app->model.result;
  printf("pitvol-board: result status=%s volume_cm3=%.17g interval_cm3=%.17g depth_mm=%.17g "
         "points_in=%llu warnings=0x%x board_warnings=0x%x dropped_events=%u\n",
         pv_status_name(app->model.result_status), app->model.result_status == PV_OK ? r->volume_cm3 : 0.0,
         r->interval_cm3, r->depth_mm, (unsigned long long)r->points_in, r->warnings,
         app->model.board_warnings, (unsigned)app->model.dropped_events);
  if (app->model.result_status != PV_OK) {
    printf("pitvol-board: refused: %s\n", pv_status_message(app->model.result_status));
  }
}

static void usb_call_failed(pv_board_app_t *app, const char *what, pv_usb_status_t st) {
  snprintf(app->model.message, sizeof app->model.message, "scanner: %s", what);
  fprintf(stderr, "pitvol-board: %s: %s\n", what, pv_usb_status_message(st));
}

static void perform(pv_board_app_t *app, unsigned act) {
  if (act & PV_ACT_BEGIN_SCAN) {
    const pv_status_t reset = pv_session_reset(app->session);
    app->scan_mark_ms = now_ms();
    if (reset != PV_OK) {
      /* The scanner is not started: its points would go into a session
       * that still holds the last scan. */
      snprintf(app->model.message, sizeof app->model.message, "core: %s", pv_status_name(reset));
      fprintf(stderr, "pitvol-board: session reset: %s\n", pv_status_message(reset));
      post(app, PV_EV_SCAN_FAILED);
    } else {
      const int old = pv_alloc_zone_enter(PV_ZONE_USB);
      const pv_usb_status_t st = pv_usb_scanner_start(app->usb);
      pv_alloc_zone_enter(old);
      if (st != PV_USB_OK) {
        usb_call_failed(app, "did not start", st);
        post(app, PV_EV_SCAN_FAILED);
      }
    }
  }
  if (act & PV_ACT_STOP_SCAN) {
    /* Waits (up to a second) for the scanner's END_OF_SCAN; its points
     * arrive through on_points meanwhile. */
    const int old = pv_alloc_zone_enter(PV_ZONE_USB);
    const pv_usb_status_t st = pv_usb_scanner_stop(app->usb);
    pv_alloc_zone_enter(old);
    if (st != PV_USB_OK) usb_call_failed(app, "did not stop", st);
  }
  /* An estimate costs more as points arrive (about 0.2-0.6 s at 300k
   * points on an x86-64 core): never more than half the loop's time, so the
   * USB transfers keep being reaped. */
  /* And none before the core's warm-up is complete: an estimate then makes
   * the core fix its levelling plane early, and on an empty session that
   * changes the final volume (a core defect, reported; seen as a flaky
   * e2e_no_scanner_at_start). After warm-up, estimates leave it alone. */
  if ((act & PV_ACT_ESTIMATE) && now_ms() >= app->next_estimate_ms &&
      app->model.points >= app->cfg.core.warmup_points) {
    const uint64_t t0 = now_ms();
    const int old = pv_alloc_zone_enter(PV_ZONE_MEASURE);
    app->model.live_status = pv_session_estimate(app->session, &app->model.live);
    pv_alloc_zone_enter(old);
    app->model.live_valid = 1;
    printf("pitvol-board: estimate %s volume_cm3=%.1f points=%llu in %llu ms\n",
           pv_status_name(app->model.live_status), app->model.live.volume_cm3,
           (unsigned long long)app->model.points, (unsigned long long)(now_ms() - t0));
    const uint64_t t1 = now_ms();
    app->next_estimate_ms = t1 + (t1 - t0);
    notify(app, PV_NEWS_ESTIMATE);
  }
  if (act & PV_ACT_MEASURE) app->measure_pending = 1;
  if (act & PV_ACT_REDRAW) app->dirty = 1;
}

static void drain_events(pv_board_app_t *app) {
  while (app->q_len > 0) {
    const pv_board_event_t ev = app->queue[app->q_head];
    app->q_head = (app->q_head + 1) % PV_BOARD_EVENT_QUEUE;
    app->q_len--;
    const pv_board_state_t before = app->model.state;
    if (ev != PV_EV_TICK) printf("pitvol-board: event %s\n", pv_board_event_name(ev));
    perform(app, pv_board_step(&app->model, ev));
    if (app->model.state != before) {
      printf("pitvol-board: state %s\n", pv_board_state_name(app->model.state));
      notify(app, PV_NEWS_STATE);
      if (ev == PV_EV_MEASURED) notify(app, PV_NEWS_RESULT);
    }
  }
}

/* The driver's state after handling its events, as board events. */
static void poll_usb(pv_board_app_t *app) {
  const int old = pv_alloc_zone_enter(PV_ZONE_USB);
  const pv_usb_state_t now = pv_usb_scanner_poll(app->usb, 0);
  pv_alloc_zone_enter(old);
  const pv_usb_state_t was = app->usb_state;
  app->usb_state = now;
  if (now == was) return;
  if (now == PV_USB_STATE_UNPLUGGED) {
    post(app, PV_EV_SCANNER_GONE);
  } else if (was == PV_USB_STATE_UNPLUGGED) {
    post(app, PV_EV_SCANNER_ARRIVED);
  }
  if (now == PV_USB_STATE_ENDED) post(app, PV_EV_SCAN_ENDED);
}

/* Density of a measured result from the mass (and moisture) set over the
 * link; the mass is used up (the next pit has its own). */
static void density(pv_board_app_t *app) {
  pv_board_model_t *m = &app->model;
  memset(&m->density, 0, sizeof m->density);
  m->result_id = 0;
  m->verdict = PV_VERDICT_NONE;
  m->decides_within_cm3 = 0;
  snprintf(m->result_test_id, sizeof m->result_test_id, "%s", m->test_id);
  if (m->result_status == PV_OK) m->test_id[0] = '\0'; /* used up, like the mass */
  if (m->result_status != PV_OK || !m->mass_set) return;
  pv_density_input_t in;
  memset(&in, 0, sizeof in);
  in.volume_cm3 = m->result.volume_cm3;
  in.interval_cm3 = m->result.interval_cm3;
  in.has_mass = 1;
  in.mass_g = m->mass_g;
  in.has_moisture = m->moisture_set;
  in.moisture_percent = m->moisture_percent;
  in.reference_max_dry_kg_m3 = app->cfg.max_dry_density_kg_m3;
  const pv_density_status_t st = pv_density_compute(&in, &m->density);
  if (st != PV_DENSITY_OK) {
    printf("pitvol-board: no density: %s\n", pv_density_status_message(st));
    return;
  }
  m->mass_set = 0;
  m->verdict = pv_density_verdict(&m->density, in.volume_cm3, app->cfg.required_compaction_percent,
                                  &m->decides_within_cm3);
  if (m->verdict != PV_VERDICT_NONE) {
    printf("pitvol-board: verdict %s against %.17g %% (decides within %.17g cm3)\n",
           pv_verdict_name(m->verdict), app->cfg.required_compaction_percent, m->decides_within_cm3);
  }
  printf("pitvol-board: density flags=0x%x mass_g=%.17g moisture_percent=%.17g wet_kg_m3=%.17g "
         "dry_kg_m3=%.17g compaction_percent=%.17g\n",
         m->density.flags, in.mass_g, in.has_moisture ? in.moisture_percent : 0.0, m->density.wet_kg_m3,
         m->density.dry_kg_m3, m->density.compaction_percent);
}

static void measure(pv_board_app_t *app) {
  app->measure_pending = 0;
  const int old = pv_alloc_zone_enter(PV_ZONE_MEASURE);
  memset(&app->model.result, 0, sizeof app->model.result);
  app->model.result_status = pv_session_finish(app->session, &app->model.result);
  pv_alloc_zone_enter(old);
  density(app);
  log_result(app);
  post(app, PV_EV_MEASURED);
}

/* Appends the failing module's status name to the sentence in err
 * ("... [PV_DISPLAY_ERR_OPEN]"): the log then names the module and the
 * fault. Returns the part of the board that failed. */
static pv_board_app_status_t failed(pv_board_app_status_t part, char *err, size_t errcap,
                                    const char *status_name) {
  const size_t n = strnlen(err, errcap);
  if (n < errcap) snprintf(err + n, errcap - n, " [%s]", status_name);
  return part;
}

/* A fault of the board's own: the sentence, then its name. */
static pv_board_app_status_t failed_own(pv_board_app_status_t st, char *err, size_t errcap) {
  return failed(st, err, errcap, pv_board_app_status_name(st));
}

pv_board_app_status_t pv_board_app_init(pv_board_app_t *app, const pv_board_config_t *cfg,
                                        char *err, size_t errcap) {
  memset(app, 0, sizeof *app);
  app->timer_fd = app->signal_fd = -1;
  app->cfg = *cfg;
  pv_board_init(&app->model);
  const pv_board_config_status_t cst = pv_board_config_check(cfg, err, errcap);
  if (cst != PV_BOARD_CONFIG_OK) return failed(PV_BOARD_APP_ERR_CONFIG, err, errcap, pv_board_config_status_name(cst));

  pv_display_status_t dst =
      pv_font_parse_psf2(&app->fonts.body, pv_font_10x20, pv_font_10x20_bytes);
  if (dst == PV_DISPLAY_OK) {
    dst = pv_font_parse_psf2(&app->fonts.big, pv_font_16x32, pv_font_16x32_bytes);
  }
  if (dst != PV_DISPLAY_OK) {
    snprintf(err, errcap, "built-in font: %s", pv_display_status_message(dst));
    return failed(PV_BOARD_APP_ERR_DISPLAY, err, errcap, pv_display_status_name(dst));
  }
  const size_t canvas_bytes =
      pv_canvas_bytes(cfg->display_width, cfg->display_height, PV_BOARD_TEXT_LOG_BYTES);
  app->canvas_mem = malloc(canvas_bytes);
  if (app->canvas_mem == NULL) {
    snprintf(err, errcap, "no memory for a %ux%u canvas", cfg->display_width, cfg->display_height);
    return failed(PV_BOARD_APP_ERR_DISPLAY, err, errcap, pv_display_status_name(PV_DISPLAY_ERR_NO_MEMORY));
  }
  dst = pv_canvas_init(&app->canvas, cfg->display_width, cfg->display_height,
                       PV_BOARD_TEXT_LOG_BYTES, app->canvas_mem, canvas_bytes);
  if (dst != PV_DISPLAY_OK) {
    snprintf(err, errcap, "canvas %ux%u: %s", cfg->display_width, cfg->display_height,
             pv_display_status_message(dst));
    return failed(PV_BOARD_APP_ERR_DISPLAY, err, errcap, pv_display_status_name(dst));
  }
  dst = pv_display_open(&app->display, cfg->display, cfg->display_width, cfg->display_height, err,
                        errcap);
  if (dst != PV_DISPLAY_OK) return failed(PV_BOARD_APP_ERR_DISPLAY, err, errcap, pv_display_status_name(dst));
  present(app); /* BOOT */

  size_t bytes = 0;
  if (pv_session_size(&cfg->core, &bytes) != PV_OK) {
    snprintf(err, errcap, "core configuration rejected");
    return failed_own(PV_BOARD_APP_ERR_CORE, err, errcap);
  }
  const size_t rounded = (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
  app->block = aligned_alloc(PV_BLOCK_ALIGN, rounded);
  if (app->block == NULL || pv_session_init(&cfg->core, app->block, bytes, &app->session) != PV_OK) {
    snprintf(err, errcap, "cannot set up the core in %zu bytes (lower core.max_layers or core.points_per_layer)", bytes);
    return failed_own(PV_BOARD_APP_ERR_CORE, err, errcap);
  }
  printf("pitvol-board: core block %zu bytes, canvas %ux%u\n", bytes, cfg->display_width,
         cfg->display_height);

  const pv_input_status_t ist = pv_input_open(&app->input, cfg->input, err, errcap);
  if (ist != PV_INPUT_OK) return failed(PV_BOARD_APP_ERR_INPUT, err, errcap, pv_input_status_name(ist));

  app->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  struct itimerspec its;
  memset(&its, 0, sizeof its);
  its.it_interval.tv_sec = cfg->estimate_period_ms / 1000u;
  its.it_interval.tv_nsec = (long)(cfg->estimate_period_ms % 1000u) * 1000000L;
  its.it_value = its.it_interval;
  if (app->timer_fd < 0 || timerfd_settime(app->timer_fd, 0, &its, NULL) != 0) {
    snprintf(err, errcap, "timer: %s", strerror(errno));
    return failed_own(PV_BOARD_APP_ERR_TIMER, err, errcap);
  }
  sigset_t mask;
  sigemptyset(&mask);
  sigaddset(&mask, SIGTERM);
  sigaddset(&mask, SIGINT);
  app->signal_fd = signalfd(-1, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
  if (app->signal_fd < 0) {
    snprintf(err, errcap, "signalfd: %s", strerror(errno));
    return failed_own(PV_BOARD_APP_ERR_SIGNAL, err, errcap);
  }

  const pv_usb_status_t ust = pv_usb_scanner_open_ids(&app->usb, cfg->usb_vendor, cfg->usb_product,
                                                      1, on_points, app);
  if (ust != PV_USB_OK) {
    snprintf(err, errcap, "USB: %s", pv_usb_status_message(ust));
    return failed(PV_BOARD_APP_ERR_USB, err, errcap, pv_usb_status_name(ust));
  }
  app->usb_state = pv_usb_scanner_poll(app->usb, 0);
  post(app, app->usb_state == PV_USB_STATE_UNPLUGGED ? PV_EV_SCANNER_GONE : PV_EV_SCANNER_ARRIVED);
  return PV_BOARD_APP_OK;
}

pv_board_app_status_t pv_board_app_run(pv_board_app_t *app, char *err, size_t errcap) {
  pv_board_app_status_t st = PV_BOARD_APP_OK;
  const int outer = pv_alloc_zone_enter(PV_ZONE_BOARD);
  while (!app->quit) {
    drain_events(app);
    const uint64_t t = now_ms();
    if (app->model.state == PV_BOARD_SCANNING || app->model.state == PV_BOARD_PAUSED) {
      app->model.scan_ms += t - app->scan_mark_ms;
    }
    app->scan_mark_ms = t;
    if (app->dirty) {
      app->dirty = 0;
      present(app);
    }
    if (app->quit) break; /* an observer or watch asked */
    if (app->measure_pending) { /* the MEASURING screen is up: now finish() */
      measure(app);
      continue;
    }

    /* One poll() over everything the board waits for. */
    int timeout = -1;
    size_t n = pv_usb_scanner_pollfds(app->usb, app->fds, PV_USB_MAX_POLLFDS, &timeout);
    const size_t i_input = n, i_timer = n + 1, i_signal = n + 2, i_watch = n + 3;
    app->fds[i_input].fd = pv_input_fd(app->input); /* -1: ignored by poll */
    app->fds[i_timer].fd = app->timer_fd;
    app->fds[i_signal].fd = app->signal_fd;
    app->fds[i_input].events = app->fds[i_timer].events = app->fds[i_signal].events = POLLIN;
    for (size_t w = 0; w < app->nwatches; ++w) {
      app->fds[i_watch + w].fd = app->watches[w].fd;
      app->fds[i_watch + w].events = app->watches[w].events;
    }
    n = i_watch + app->nwatches;
    for (size_t i = i_input; i < n; ++i) app->fds[i].revents = 0;
    const int r = poll(app->fds, (nfds_t)n, timeout);
    if (r < 0 && errno != EINTR) {
      /* A loop that cannot wait is no board: stop with a failure, so that
       * systemd restarts it, instead of ending as if asked to. */
      snprintf(err, errcap, "poll: %s", strerror(errno));
      st = failed_own(PV_BOARD_APP_ERR_POLL, err, errcap);
      break;
    }
    if (r > 0 && (app->fds[i_signal].revents & POLLIN)) {
      struct signalfd_siginfo si;
      if (read(app->signal_fd, &si, sizeof si) > 0) {
        printf("pitvol-board: signal %u, stopping\n", si.ssi_signo);
        app->quit = 1;
      }
    }
    if (r > 0 && (app->fds[i_timer].revents & POLLIN)) {
      uint64_t expirations = 0;
      if (read(app->timer_fd, &expirations, sizeof expirations) > 0) {
        post(app, PV_EV_TICK); /* late ticks fold into one */
      }
    }
    if (r > 0 && (app->fds[i_input].revents & POLLIN)) {
      pv_key_t keys[8];
      char ierr[128];
      size_t k = 0;
      const pv_input_status_t ist = pv_input_read(app->input, keys, 8, &k, ierr, sizeof ierr);
      if (ist != PV_INPUT_OK) {
        fprintf(stderr, "pitvol-board: %s [%s]\n", ierr, pv_input_status_name(ist));
      }
      for (size_t i = 0; i < k; ++i) {
        static const pv_board_event_t kKeyEvent[] = {PV_EV_START_STOP, PV_EV_START_STOP,
                                                     PV_EV_ENTER, PV_EV_BACK};
        printf("pitvol-board: button %s\n", pv_key_name(keys[i]));
        post(app, kKeyEvent[keys[i]]);
      }
    }
    for (size_t w = 0; r > 0 && w < app->nwatches; ++w) {
      if (app->fds[i_watch + w].revents != 0) {
        app->watches[w].fn(app, app->watches[w].fd, app->fds[i_watch + w].revents, app->watches[w].user);
      }
    }
    poll_usb(app);
  }
  pv_alloc_zone_enter(outer);
  return st;
}

void pv_board_app_close(pv_board_app_t *app) {
  pv_usb_scanner_close(app->usb);
  pv_input_close(app->input);
  pv_display_close(app->display);
  if (app->timer_fd >= 0) close(app->timer_fd);
  if (app->signal_fd >= 0) close(app->signal_fd);
  free(app->canvas_mem);
  free(app->block);
  memset(app, 0, sizeof *app);
}
