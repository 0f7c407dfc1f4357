/* The board's serial link and result log (board_link.h). */
#include "board_link.h"

#include "board_clock.h"
#include "board_record.h"
#include "board_refusal.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <pb_decode.h>
#include <pb_encode.h>

#include "pitvol/density.h"
#include "pitvol/user_input.h"

_Static_assert(PV_DENSITY_WET == pitvol_DensityFlag_DENSITY_WET, "density flags = protocol flags");
_Static_assert(PV_DENSITY_DRY == pitvol_DensityFlag_DENSITY_DRY, "density flags = protocol flags");
_Static_assert(PV_DENSITY_COMPACTION == pitvol_DensityFlag_DENSITY_COMPACTION, "density flags");
_Static_assert(PV_DENSITY_UNBOUNDED == pitvol_DensityFlag_DENSITY_UNBOUNDED, "density flags");
_Static_assert(PV_COVERAGE_BANDS <= sizeof(((pitvol_Status *)0)->coverage) / sizeof(float),
               "Status.coverage holds every band");

/* Error.code of a board fault: the result log refused. The first code of
 * the board's range (pitvol/status_codes.h), on the wire since protocol 1. */
#define PV_BOARD_ERR_LOG PV_STATUS_BASE_BOARD
_Static_assert(PV_BOARD_ERR_LOG == 100, "Error.code 100 is the log fault on the wire");

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

static void outbox_push(pv_board_link_t *bl, const pitvol_Message *m, int is_reply, uint32_t reply_to) {
  if (bl->out_len == PV_BOARD_LINK_OUTBOX) {
    /* Nobody reads the port. A Result is in the log (GetResults), an answer
     * is kept by the link for the host's repeat: nothing is lost for good. */
    bl->out_dropped++;
    return;
  }
  const uint32_t i = (bl->out_head + bl->out_len) % PV_BOARD_LINK_OUTBOX;
  bl->outbox[i].msg = *m;
  bl->outbox[i].is_reply = is_reply;
  bl->outbox[i].reply_to = reply_to;
  bl->out_len++;
}

static void pump_outbox(pv_board_link_t *bl) {
  while (bl->out_len > 0) {
    const uint32_t i = bl->out_head;
    const pv_link_status_t st =
        bl->outbox[i].is_reply
            ? pv_link_send_reply(&bl->link, bl->outbox[i].reply_to, &bl->outbox[i].msg)
            : pv_link_send(&bl->link, &bl->outbox[i].msg, PV_LINK_RELIABLE, NULL);
    if (st == PV_LINK_QUEUE_FULL) return;
    if (st != PV_LINK_OK) {
      printf("pitvol-board: link: %s dropped: %s\n", pv_link_message_name(&bl->outbox[i].msg),
             pv_link_status_message(st));
    }
    bl->out_head = (bl->out_head + 1) % PV_BOARD_LINK_OUTBOX;
    bl->out_len--;
  }
}

static void send_reliable(pv_board_link_t *bl, const pitvol_Message *m) {
  outbox_push(bl, m, 0, 0);
  pump_outbox(bl);
}

/* Answers wait behind the messages their command produced (Hello before
 * its Ack) and go through pv_link_send_reply, kept for a repeated command. */
static void reply(pv_board_link_t *bl, const pitvol_Message *m) {
  const uint32_t to = m->which_body == pitvol_Message_ack_tag ? m->body.ack.command_seq
                                                                : m->body.nack.command_seq;
  outbox_push(bl, m, 1, to);
  pump_outbox(bl);
}

static void ack(pv_board_link_t *bl, uint32_t seq, uint32_t sent) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_ack_tag;
  m.body.ack.command_seq = seq;
  m.body.ack.first_id = bl->have_log ? pv_log_first_seq(&bl->log) : 0;
  m.body.ack.last_id = bl->have_log ? pv_log_last_seq(&bl->log) : 0;
  m.body.ack.sent_count = sent;
  reply(bl, &m);
}

static void nack(pv_board_link_t *bl, uint32_t seq, pitvol_NackCode code, const char *reason) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_nack_tag;
  m.body.nack.command_seq = seq;
  m.body.nack.code = code;
  snprintf(m.body.nack.reason, sizeof m.body.nack.reason, "%s", reason);
  reply(bl, &m);
}

static void send_error(pv_board_link_t *bl, int32_t code, const char *name, const char *message) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_error_tag;
  m.body.error.code = code;
  snprintf(m.body.error.name, sizeof m.body.error.name, "%s", name);
  snprintf(m.body.error.message, sizeof m.body.error.message, "%s", message);
  send_reliable(bl, &m);
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

static void send_status(pv_board_link_t *bl) {
  const pv_board_model_t *md = &bl->app->model;
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_status_tag;
  pitvol_Status *s = &m.body.status;
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
  s->last_result_id = bl->have_log ? pv_log_last_seq(&bl->log) : 0;
  s->mass_set = md->mass_set != 0;
  s->mass_g = md->mass_set ? md->mass_g : 0;
  s->moisture_set = md->moisture_set != 0;
  s->moisture_percent = md->moisture_set ? md->moisture_percent : 0;
  s->frames_corrupt = bl->link.stats.frames_corrupt;
  /* A Status the queue has no room for is dropped and counted by the link
   * (lossy_dropped, printed at exit): the next one replaces it. */
  const pv_link_status_t st = pv_link_send(&bl->link, &m, PV_LINK_LOSSY, NULL);
  (void)st;
}

static void send_hello(pv_board_link_t *bl) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_hello_tag;
  pitvol_Hello *h = &m.body.hello;
  h->protocol_version = PV_LINK_PROTOCOL_VERSION;
  snprintf(h->firmware_version, sizeof h->firmware_version, "%s", PV_VERSION_STRING);
  snprintf(h->device_id, sizeof h->device_id, "%s", bl->app->cfg.device_id);
  h->capabilities = (bl->have_log ? pitvol_Capability_CAP_RESULT_LOG : 0) |
                    pitvol_Capability_CAP_DENSITY | pitvol_Capability_CAP_LIVE_ESTIMATE;
  h->max_frame_bytes = PV_LINK_MAX_WIRE_BYTES;
  h->first_result_id = bl->have_log ? pv_log_first_seq(&bl->log) : 0;
  h->last_result_id = bl->have_log ? pv_log_last_seq(&bl->log) : 0;
  send_reliable(bl, &m);
}

/* Streams a GetResults answer from the log as the link drains: the queue
 * never holds more than its 8 frames however long the log. */
static void continue_fetch(pv_board_link_t *bl) {
  while (bl->fetch.on && bl->out_len == 0 && pv_link_tx_room(&bl->link) > 2) {
    uint8_t buf[PV_LOG_MAX_PAYLOAD_BYTES];
    uint32_t seq = 0;
    size_t len = 0;
    const pv_log_status_t st = pv_log_next(&bl->log, &bl->fetch.cur, buf, sizeof buf, &seq, &len);
    if (st == PV_LOG_END || (st == PV_LOG_OK && seq > bl->fetch.to_id)) {
      bl->fetch.on = 0;
      ack(bl, bl->fetch.cmd_seq, bl->fetch.sent);
      return;
    }
    if (st != PV_LOG_OK) {
      bl->fetch.on = 0;
      nack(bl, bl->fetch.cmd_seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(st));
      return;
    }
    pitvol_Message m = pitvol_Message_init_zero;
    m.which_body = pitvol_Message_result_tag;
    pb_istream_t is = pb_istream_from_buffer(buf, len);
    if (!pb_decode(&is, pitvol_Result_fields, &m.body.result)) {
      printf("pitvol-board: result log record %u does not decode: skipped\n", seq);
      continue; /* the host names the gap */
    }
    if (pv_link_send(&bl->link, &m, PV_LINK_RELIABLE, NULL) != PV_LINK_OK) {
      /* this one again after a flush */
      const pv_log_status_t sst = pv_log_seek(&bl->log, seq, &bl->fetch.cur);
      if (sst != PV_LOG_OK) {
        bl->fetch.on = 0;
        nack(bl, bl->fetch.cmd_seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(sst));
      }
      return;
    }
    bl->fetch.sent++;
  }
}

/* Queued frames out as far as the port takes them; poll for POLLOUT while
 * any remain. */
static void service(pv_board_link_t *bl) {
  if (!bl->have_port) return;
  for (int round = 0; round < 4; ++round) {
    pump_outbox(bl);
    continue_fetch(bl);
    if (pv_link_tx_flush(&bl->link, write_port, bl) != PV_LINK_OK) break;
    if (pv_link_tx_pending(&bl->link)) break; /* the port is full */
    if (bl->out_len == 0 && !bl->fetch.on) break;
  }
  if (pv_board_app_watch_events(bl->app, pv_serial_fd(&bl->port),
                                (short)(POLLIN | (pv_link_tx_pending(&bl->link) ? POLLOUT : 0))) != 0) {
    fprintf(stderr, "pitvol-board: link: the port is not watched; nothing will be sent\n");
  }
}

/* Mass and moisture against their plausible ranges (pitvol/user_input.h,
 * the numbers of pitvol/density.h): the refusal names the range. */
static void set_density_input(pv_board_link_t *bl, const pv_link_rx_t *rx, int moisture) {
  const double v = moisture ? rx->msg.body.set_moisture.moisture_percent : rx->msg.body.set_mass.mass_g;
  char why[sizeof(((pitvol_Nack *)0)->reason)];
  if (pv_input_check(moisture ? PV_INPUT_MOISTURE_PERCENT : PV_INPUT_MASS_G, v, why, sizeof why) != 0) {
    nack(bl, rx->seq, pitvol_NackCode_NACK_OUT_OF_RANGE, why);
    return;
  }
  pv_board_model_t *m = &bl->app->model;
  if (moisture) {
    m->moisture_set = 1;
    m->moisture_percent = v;
    printf("pitvol-board: link: moisture %.17g %%\n", v);
  } else {
    m->mass_set = 1;
    m->mass_g = v;
    printf("pitvol-board: link: mass %.17g g\n", v);
  }
  ack(bl, rx->seq, 0);
}

/* The record from the configuration and the model, as board_record.h
 * works on it. */
static pv_board_record_t current_record(const pv_board_app_t *app) {
  pv_board_record_t rec;
  memset(&rec, 0, sizeof rec);
  snprintf(rec.test_id, sizeof rec.test_id, "%s", app->model.test_id);
  snprintf(rec.location, sizeof rec.location, "%s", app->cfg.location);
  snprintf(rec.operator_name, sizeof rec.operator_name, "%s", app->cfg.operator_name);
  rec.max_dry_density_kg_m3 = app->cfg.max_dry_density_kg_m3;
  rec.required_compaction_percent = app->cfg.required_compaction_percent;
  return rec;
}

static void set_record(pv_board_link_t *bl, const pv_link_rx_t *rx) {
  pv_board_record_t rec = current_record(bl->app);
  char why[sizeof(((pitvol_Nack *)0)->reason)];
  if (pv_board_record_apply(&rec, &rx->msg.body.set_record, why, sizeof why) != 0) {
    nack(bl, rx->seq, pitvol_NackCode_NACK_OUT_OF_RANGE, why);
    return;
  }
  pv_board_app_t *app = bl->app;
  snprintf(app->model.test_id, sizeof app->model.test_id, "%s", rec.test_id);
  snprintf(app->cfg.location, sizeof app->cfg.location, "%s", rec.location);
  snprintf(app->cfg.operator_name, sizeof app->cfg.operator_name, "%s", rec.operator_name);
  app->cfg.max_dry_density_kg_m3 = rec.max_dry_density_kg_m3;
  app->cfg.required_compaction_percent = rec.required_compaction_percent;
  printf("pitvol-board: link: record test_id=%s location=%s operator=%s max_dry=%.17g required=%.17g\n",
         rec.test_id, rec.location, rec.operator_name, rec.max_dry_density_kg_m3,
         rec.required_compaction_percent);
  ack(bl, rx->seq, 0);
}

static void post_or_busy(pv_board_link_t *bl, const pv_link_rx_t *rx, pv_board_event_t ev) {
  if (pv_board_app_post(bl->app, ev) != 0) {
    nack(bl, rx->seq, pitvol_NackCode_NACK_BUSY, "the board is busy; send the command again");
  } else {
    ack(bl, rx->seq, 0);
  }
}

static void handle(pv_board_link_t *bl, const pv_link_rx_t *rx) {
  const pv_board_model_t *m = &bl->app->model;
  printf("pitvol-board: link: %s\n", pv_link_message_name(&rx->msg));
  switch (rx->msg.which_body) {
    case pitvol_Message_get_hello_tag:
      send_hello(bl);
      ack(bl, rx->seq, 0);
      break;
    case pitvol_Message_start_scan_tag:
      /* The START button's event, where the button would start a scan. */
      if (m->state == PV_BOARD_IDLE || m->state == PV_BOARD_RESULT || m->state == PV_BOARD_REFUSED ||
          (m->state == PV_BOARD_NO_SCANNER && !m->armed)) {
        post_or_busy(bl, rx, PV_EV_START_STOP);
      } else {
        nack(bl, rx->seq, pitvol_NackCode_NACK_WRONG_STATE,
             m->state == PV_BOARD_NO_SCANNER ? "a scan already waits for the scanner; plug it in"
                                             : "a scan is already running; stop it first");
      }
      break;
    case pitvol_Message_stop_scan_tag:
      if ((m->state == PV_BOARD_SCANNING && !m->stopping) || m->state == PV_BOARD_PAUSED) {
        post_or_busy(bl, rx, PV_EV_START_STOP);
      } else if (m->state == PV_BOARD_NO_SCANNER && m->armed) {
        post_or_busy(bl, rx, PV_EV_BACK); /* the waiting scan is called off */
      } else {
        nack(bl, rx->seq, pitvol_NackCode_NACK_WRONG_STATE, "no scan is running; start one first");
      }
      break;
    case pitvol_Message_set_mass_tag:
      set_density_input(bl, rx, 0);
      break;
    case pitvol_Message_set_moisture_tag:
      set_density_input(bl, rx, 1);
      break;
    case pitvol_Message_set_record_tag:
      set_record(bl, rx);
      break;
    case pitvol_Message_get_results_tag:
      if (!bl->have_log) {
        nack(bl, rx->seq, pitvol_NackCode_NACK_STORAGE,
             "this board keeps no result log (result_log = none in its configuration)");
        break;
      }
      if (bl->fetch.on) ack(bl, bl->fetch.cmd_seq, bl->fetch.sent); /* a newer request replaces it */
      memset(&bl->fetch, 0, sizeof bl->fetch);
      bl->fetch.cmd_seq = rx->seq;
      bl->fetch.to_id = rx->msg.body.get_results.to_id ? rx->msg.body.get_results.to_id : UINT32_MAX;
      if (pv_log_seek(&bl->log, rx->msg.body.get_results.from_id, &bl->fetch.cur) != PV_LOG_OK) {
        nack(bl, rx->seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(PV_LOG_ERR_IO));
      } else {
        bl->fetch.on = 1;
      }
      break;
    default:
      nack(bl, rx->seq, pitvol_NackCode_NACK_UNKNOWN_COMMAND, "this board does not know that command");
      break;
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
    if (st == PV_SERIAL_OK) {
      for (size_t at = 0; at < n;) {
        pv_link_rx_t rx;
        int got = 0;
        at += pv_link_feed(&bl->link, buf + at, n - at, &rx, &got);
        if (got) handle(bl, &rx);
      }
    }
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
  if (s == PV_BOARD_SCANNING || s == PV_BOARD_PAUSED || bl->ticks % 4u == 0) send_status(bl);
  service(bl);
}


/* The result: into the log (durable), then out; its id is the record number. */
static void on_result(pv_board_link_t *bl) {
  pv_board_model_t *md = &bl->app->model;
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_result_tag;
  pitvol_Result *r = &m.body.result;
  const pv_result_t *res = &md->result;
  r->time_unix_s = pv_board_result_time((int64_t)time(NULL));
  r->status = (int32_t)md->result_status;
  snprintf(r->method, sizeof r->method, "%s", pv_method_name(bl->app->cfg.core.method));
  if (md->result_status == PV_OK) {
    r->volume_cm3 = res->volume_cm3;
    r->interval_cm3 = res->interval_cm3;
    r->depth_mm = res->depth_mm;
  }
  pv_board_result_refusal(r, md->result_status, res);
  r->warnings = res->warnings;
  r->unseen_share = res->unseen_share;
  r->points_in = res->points_in;
  r->points_used = res->points_used;
  const pv_density_t *d = &md->density;
  if (d->flags & PV_DENSITY_WET) {
    r->has_density = true;
    pitvol_Density *p = &r->density;
    p->flags = d->flags;
    p->mass_g = md->mass_g;
    p->moisture_percent = (d->flags & PV_DENSITY_DRY) ? md->moisture_percent : 0;
    p->wet_kg_m3 = d->wet_kg_m3;
    p->wet_low_kg_m3 = d->wet_low_kg_m3;
    p->wet_high_kg_m3 = d->wet_high_kg_m3;
    p->dry_kg_m3 = d->dry_kg_m3;
    p->dry_low_kg_m3 = d->dry_low_kg_m3;
    p->dry_high_kg_m3 = d->dry_high_kg_m3;
    p->reference_max_dry_kg_m3 = (d->flags & PV_DENSITY_COMPACTION) ? bl->app->cfg.max_dry_density_kg_m3 : 0;
    p->compaction_percent = d->compaction_percent;
    p->compaction_low_percent = d->compaction_low_percent;
    p->compaction_high_percent = d->compaction_high_percent;
  }
  /* The record the result was taken under (its test id was used up by it). */
  pv_board_record_t rec = current_record(bl->app);
  snprintf(rec.test_id, sizeof rec.test_id, "%s", md->result_test_id);
  pv_board_result_record(r, &rec, d, md->result_status == PV_OK ? res->volume_cm3 : 0.0);
  if (bl->have_log) {
    r->id = pv_log_last_seq(&bl->log) + 1;
    uint8_t buf[pitvol_Result_size];
    pb_ostream_t os = pb_ostream_from_buffer(buf, sizeof buf);
    uint32_t seq = 0;
    pv_log_status_t st = PV_LOG_ERR_TOO_LARGE;
    if (pb_encode(&os, pitvol_Result_fields, r)) st = pv_log_append(&bl->log, buf, os.bytes_written, &seq);
    if (st == PV_LOG_OK && seq == r->id) {
      md->result_id = seq;
      printf("pitvol-board: logged result id=%u (%zu bytes)\n", seq, os.bytes_written);
    } else {
      printf("pitvol-board: result not logged: %s\n", pv_log_status_message(st));
      r->id = 0;
      if (bl->have_port) send_error(bl, PV_BOARD_ERR_LOG, "PV_BOARD_LOG", pv_log_status_message(st));
    }
  }
  if (!bl->have_port) return;
  send_reliable(bl, &m);
  if (md->result_status != PV_OK) {
    send_error(bl, (int32_t)md->result_status, pv_status_name(md->result_status),
               pv_status_message(md->result_status));
  }
  send_status(bl);
}

static void on_news(pv_board_app_t *app, pv_board_news_t what, const pv_board_model_t *m, void *user) {
  (void)app;
  pv_board_link_t *bl = (pv_board_link_t *)user;
  if (what == PV_NEWS_RESULT) {
    on_result(bl);
  } else if (what == PV_NEWS_ESTIMATE && bl->have_port) {
    send_status(bl); /* the running volume as soon as it is known */
  } else if (what == PV_NEWS_STATE && bl->have_port && m->state != PV_BOARD_RESULT &&
             m->state != PV_BOARD_REFUSED) {
    send_status(bl); /* (a new result's Status follows the Result, with its id) */
  }
  service(bl);
}

int pv_board_link_start(pv_board_link_t *bl, pv_board_app_t *app, int adopt_fd, char *err,
                        size_t errcap) {
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
      return -1;
    }
    bl->have_log = 1;
    const pv_log_recovery_t *rec = &bl->log.recovery;
    printf("pitvol-board: result log %s: results %u..%u, %u segments, %u torn bytes dropped\n",
           cfg->result_log, pv_log_first_seq(&bl->log), pv_log_last_seq(&bl->log), rec->segments,
           rec->torn_bytes);
  } else {
    printf("pitvol-board: no result log (result_log = none): results are not kept\n");
  }
  pv_board_app_set_observer(app, on_news, bl); /* results go to the log with or without a port */
  pv_serial_status_t sst = PV_SERIAL_ERR_OPEN;
  if (adopt_fd >= 0) {
    sst = pv_serial_adopt(&bl->port, adopt_fd, cfg->serial_baud);
  } else if (strcmp(cfg->serial, "none") != 0) {
    sst = pv_serial_open(&bl->port, cfg->serial, cfg->serial_baud);
  } else {
    printf("pitvol-board: serial link off (serial = none)\n");
    return 0;
  }
  if (sst != PV_SERIAL_OK) {
    /* The board still measures and logs; the link is what is missing. */
    printf("pitvol-board: serial link off: %s: %s\n", adopt_fd >= 0 ? "pty" : cfg->serial,
           pv_serial_status_message(sst));
    return 0;
  }
  pv_link_init(&bl->link, (uint32_t)time(NULL));
  bl->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  struct itimerspec its;
  memset(&its, 0, sizeof its);
  its.it_interval.tv_nsec = (long)PV_BOARD_LINK_STATUS_MS * 1000000L;
  its.it_value = its.it_interval;
  if (bl->timer_fd < 0 || timerfd_settime(bl->timer_fd, 0, &its, NULL) != 0 ||
      pv_board_app_watch(app, pv_serial_fd(&bl->port), POLLIN, on_port, bl) != 0 ||
      pv_board_app_watch(app, bl->timer_fd, POLLIN, on_timer, bl) != 0) {
    snprintf(err, errcap, "serial link: cannot set up its timer or watches (%s)", strerror(errno));
    return -1;
  }
  bl->have_port = 1;
  printf("pitvol-board: serial link on %s at %u baud\n", adopt_fd >= 0 ? "pty" : cfg->serial,
         cfg->serial_baud);
  send_status(bl);
  service(bl);
  return 0;
}

void pv_board_link_stop(pv_board_link_t *bl) {
  if (bl->app == NULL) return; /* never started */
  if (bl->have_port) {
    if (pv_link_tx_flush(&bl->link, write_port, bl) != PV_LINK_OK) {
      printf("pitvol-board: link: writing the port failed: %u frames not sent\n",
             bl->link.tx_count);
    }
    const pv_link_stats_t *s = &bl->link.stats;
    printf("pitvol-board: link: %u frames sent, %u received, %u corrupt, %u missed, %u repeated "
           "commands, %u status dropped, %u outbox dropped, %u host restarts\n",
           s->frames_sent, s->frames_received, s->frames_corrupt, s->frames_missed,
           s->commands_duplicate, s->lossy_dropped, bl->out_dropped, s->peer_restarts);
    pv_serial_close(&bl->port);
  }
  bl->app->observer = NULL;
  if (bl->timer_fd >= 0) close(bl->timer_fd);
  if (bl->have_log) pv_log_close(&bl->log);
  bl->have_port = bl->have_log = 0;
  bl->timer_fd = -1;
}
