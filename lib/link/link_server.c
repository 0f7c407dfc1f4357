/* The device end of the serial link (pitvol/link_server.h). */
#include "pitvol/link_server.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <pb_decode.h>
#include <pb_encode.h>

_Static_assert(PV_LINK_SERVER_ERR_LOG == 100, "Error.code 100 is the log fault on the wire");

static void note(pv_link_server_t *srv, const char *fmt, ...) {
  if (!srv->cfg.app->note) return;
  char line[200];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  srv->cfg.app->note(srv->cfg.ctx, line);
}

static uint32_t first_id(const pv_link_server_t *srv) {
  return srv->cfg.log ? pv_log_first_seq(srv->cfg.log) : 0;
}

static uint32_t last_id(const pv_link_server_t *srv) {
  return srv->cfg.log ? pv_log_last_seq(srv->cfg.log) : 0;
}

static void outbox_push(pv_link_server_t *srv, const pitvol_Message *m, int is_reply,
                        uint32_t reply_to) {
  if (srv->out_len == PV_LINK_SERVER_OUTBOX) {
    /* Nobody reads the port. A Result is in the log (GetResults), an answer
     * is kept by the link for the host's repeat: nothing is lost for good. */
    srv->out_dropped++;
    return;
  }
  pv_link_server_out_t *o = &srv->outbox[(srv->out_head + srv->out_len) % PV_LINK_SERVER_OUTBOX];
  o->msg = *m;
  o->is_reply = (uint8_t)is_reply;
  o->reply_to = reply_to;
  srv->out_len++;
}

static void pump_outbox(pv_link_server_t *srv) {
  while (srv->out_len > 0) {
    pv_link_server_out_t *o = &srv->outbox[srv->out_head];
    const pv_link_status_t st = o->is_reply ? pv_link_send_reply(&srv->link, o->reply_to, &o->msg)
                                            : pv_link_send(&srv->link, &o->msg, PV_LINK_RELIABLE, NULL);
    if (st == PV_LINK_QUEUE_FULL) return;
    if (st != PV_LINK_OK) {
      note(srv, "link: %s dropped: %s", pv_link_message_name(&o->msg), pv_link_status_message(st));
    }
    srv->out_head = (srv->out_head + 1) % PV_LINK_SERVER_OUTBOX;
    srv->out_len--;
  }
}

static void send_reliable(pv_link_server_t *srv, const pitvol_Message *m) {
  outbox_push(srv, m, 0, 0);
  pump_outbox(srv);
}

/* Answers wait behind the messages their command produced (Hello before
 * its Ack) and go through pv_link_send_reply, kept for a repeated command. */
static void reply(pv_link_server_t *srv, const pitvol_Message *m) {
  const uint32_t to = m->which_body == pitvol_Message_ack_tag ? m->body.ack.command_seq
                                                                : m->body.nack.command_seq;
  outbox_push(srv, m, 1, to);
  pump_outbox(srv);
}

static void ack(pv_link_server_t *srv, uint32_t seq, uint32_t sent) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_ack_tag;
  m.body.ack.command_seq = seq;
  m.body.ack.first_id = first_id(srv);
  m.body.ack.last_id = last_id(srv);
  m.body.ack.sent_count = sent;
  reply(srv, &m);
}

static void nack(pv_link_server_t *srv, uint32_t seq, pitvol_NackCode code, const char *reason) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_nack_tag;
  m.body.nack.command_seq = seq;
  m.body.nack.code = code;
  snprintf(m.body.nack.reason, sizeof m.body.nack.reason, "%s", reason);
  reply(srv, &m);
}

static void send_error(pv_link_server_t *srv, int32_t code, const char *name, const char *message) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_error_tag;
  m.body.error.code = code;
  snprintf(m.body.error.name, sizeof m.body.error.name, "%s", name);
  snprintf(m.body.error.message, sizeof m.body.error.message, "%s", message);
  send_reliable(srv, &m);
}

static void send_hello(pv_link_server_t *srv) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_hello_tag;
  pitvol_Hello *h = &m.body.hello;
  h->protocol_version = PV_LINK_PROTOCOL_VERSION;
  snprintf(h->firmware_version, sizeof h->firmware_version, "%s", PV_VERSION_STRING);
  snprintf(h->device_id, sizeof h->device_id, "%s", srv->cfg.device_id ? srv->cfg.device_id : "");
  h->capabilities = srv->cfg.capabilities | (srv->cfg.log ? pitvol_Capability_CAP_RESULT_LOG : 0);
  h->max_frame_bytes = PV_LINK_MAX_WIRE_BYTES;
  h->first_result_id = first_id(srv);
  h->last_result_id = last_id(srv);
  send_reliable(srv, &m);
}

void pv_link_server_send_status(pv_link_server_t *srv) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_status_tag;
  srv->cfg.app->status(srv->cfg.ctx, &m.body.status);
  m.body.status.last_result_id = last_id(srv);
  m.body.status.frames_corrupt = srv->link.stats.frames_corrupt;
  /* A Status the queue has no room for is dropped and counted by the link
   * (lossy_dropped): the next one replaces it. */
  const pv_link_status_t st = pv_link_send(&srv->link, &m, PV_LINK_LOSSY, NULL);
  (void)st;
}

/* Streams a GetResults answer from the log as the link drains: the queue
 * never holds more than its frames however long the log. */
static void continue_fetch(pv_link_server_t *srv) {
  while (srv->fetch.on && srv->out_len == 0 && pv_link_tx_room(&srv->link) > 2) {
    uint8_t buf[PV_LOG_MAX_PAYLOAD_BYTES];
    uint32_t seq = 0;
    size_t len = 0;
    const pv_log_status_t st = pv_log_next(srv->cfg.log, &srv->fetch.cur, buf, sizeof buf, &seq, &len);
    if (st == PV_LOG_END || (st == PV_LOG_OK && seq > srv->fetch.to_id)) {
      srv->fetch.on = 0;
      ack(srv, srv->fetch.cmd_seq, srv->fetch.sent);
      return;
    }
    if (st != PV_LOG_OK) {
      srv->fetch.on = 0;
      nack(srv, srv->fetch.cmd_seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(st));
      return;
    }
    pitvol_Message m = pitvol_Message_init_zero;
    m.which_body = pitvol_Message_result_tag;
    pb_istream_t is = pb_istream_from_buffer(buf, len);
    if (!pb_decode(&is, pitvol_Result_fields, &m.body.result)) {
      note(srv, "result log record %u does not decode: skipped", seq);
      continue; /* the host names the gap */
    }
    if (pv_link_send(&srv->link, &m, PV_LINK_RELIABLE, NULL) != PV_LINK_OK) {
      /* The cursor is past this record already: back to it, for the next
       * round after a flush, or the host would see a gap. */
      const pv_log_status_t sst = pv_log_seek(srv->cfg.log, seq, &srv->fetch.cur);
      if (sst != PV_LOG_OK) {
        srv->fetch.on = 0;
        nack(srv, srv->fetch.cmd_seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(sst));
      }
      return;
    }
    srv->fetch.sent++;
  }
}

pv_link_status_t pv_link_server_service(pv_link_server_t *srv, pv_link_write_fn write,
                                        void *write_ctx) {
  for (int round = 0; round < 4; ++round) {
    pump_outbox(srv);
    continue_fetch(srv);
    const pv_link_status_t st = pv_link_tx_flush(&srv->link, write, write_ctx);
    if (st != PV_LINK_OK) return st;
    if (pv_link_tx_pending(&srv->link)) break; /* the port is full */
    if (srv->out_len == 0 && !srv->fetch.on) break;
  }
  return PV_LINK_OK;
}

int pv_link_server_busy(const pv_link_server_t *srv) {
  return srv->out_len > 0 || srv->fetch.on || pv_link_tx_pending(&srv->link);
}

/* Mass and moisture against their plausible ranges: the refusal names the
 * range. */
static void set_density_input(pv_link_server_t *srv, const pv_link_rx_t *rx, pv_input_kind_t kind) {
  const double v = kind == PV_INPUT_MOISTURE_PERCENT ? rx->msg.body.set_moisture.moisture_percent
                                                     : rx->msg.body.set_mass.mass_g;
  char why[sizeof(((pitvol_Nack *)0)->reason)];
  if (pv_input_check(kind, v, why, sizeof why) != 0) {
    nack(srv, rx->seq, pitvol_NackCode_NACK_OUT_OF_RANGE, why);
    return;
  }
  srv->cfg.app->set_density_input(srv->cfg.ctx, kind, v);
  ack(srv, rx->seq, 0);
}

static void set_record(pv_link_server_t *srv, const pv_link_rx_t *rx) {
  pv_link_record_t rec;
  memset(&rec, 0, sizeof rec);
  srv->cfg.app->get_record(srv->cfg.ctx, &rec);
  char why[sizeof(((pitvol_Nack *)0)->reason)];
  if (pv_link_record_apply(&rec, &rx->msg.body.set_record, why, sizeof why) != PV_LINK_OK) {
    /* The sentence names the field and its limit; the Nack carries it. */
    nack(srv, rx->seq, pitvol_NackCode_NACK_OUT_OF_RANGE, why);
    return;
  }
  srv->cfg.app->set_record(srv->cfg.ctx, &rec);
  ack(srv, rx->seq, 0);
}

static void scan_command(pv_link_server_t *srv, const pv_link_rx_t *rx,
                         pitvol_NackCode (*decide)(void *, char *, size_t)) {
  char why[sizeof(((pitvol_Nack *)0)->reason)] = "";
  const pitvol_NackCode code = decide(srv->cfg.ctx, why, sizeof why);
  if (code == pitvol_NackCode_NACK_NONE) {
    ack(srv, rx->seq, 0);
  } else {
    nack(srv, rx->seq, code, why);
  }
}

static void get_results(pv_link_server_t *srv, const pv_link_rx_t *rx) {
  if (!srv->cfg.log) {
    nack(srv, rx->seq, pitvol_NackCode_NACK_STORAGE,
         "this board keeps no result log (result_log = none in its configuration)");
    return;
  }
  if (srv->fetch.on) ack(srv, srv->fetch.cmd_seq, srv->fetch.sent); /* a newer request replaces it */
  memset(&srv->fetch, 0, sizeof srv->fetch);
  srv->fetch.cmd_seq = rx->seq;
  srv->fetch.to_id = rx->msg.body.get_results.to_id ? rx->msg.body.get_results.to_id : UINT32_MAX;
  if (pv_log_seek(srv->cfg.log, rx->msg.body.get_results.from_id, &srv->fetch.cur) != PV_LOG_OK) {
    nack(srv, rx->seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(PV_LOG_ERR_IO));
  } else {
    srv->fetch.on = 1;
  }
}

static void handle(pv_link_server_t *srv, const pv_link_rx_t *rx) {
  note(srv, "link: %s", pv_link_message_name(&rx->msg));
  switch (rx->msg.which_body) {
    case pitvol_Message_get_hello_tag:
      send_hello(srv);
      ack(srv, rx->seq, 0);
      break;
    case pitvol_Message_start_scan_tag: scan_command(srv, rx, srv->cfg.app->start_scan); break;
    case pitvol_Message_stop_scan_tag: scan_command(srv, rx, srv->cfg.app->stop_scan); break;
    case pitvol_Message_set_mass_tag: set_density_input(srv, rx, PV_INPUT_MASS_G); break;
    case pitvol_Message_set_moisture_tag: set_density_input(srv, rx, PV_INPUT_MOISTURE_PERCENT); break;
    case pitvol_Message_set_record_tag: set_record(srv, rx); break;
    case pitvol_Message_get_results_tag: get_results(srv, rx); break;
    default:
      nack(srv, rx->seq, pitvol_NackCode_NACK_UNKNOWN_COMMAND, "this board does not know that command");
      break;
  }
}

void pv_link_server_feed(pv_link_server_t *srv, const uint8_t *data, size_t len) {
  for (size_t at = 0; at < len;) {
    pv_link_rx_t rx;
    int got = 0;
    at += pv_link_feed(&srv->link, data + at, len - at, &rx, &got);
    if (got) handle(srv, &rx);
  }
}

void pv_link_server_init(pv_link_server_t *srv, const pv_link_server_config_t *cfg) {
  memset(srv, 0, sizeof *srv);
  srv->cfg = *cfg;
  pv_link_init(&srv->link, cfg->first_seq);
}

pv_log_status_t pv_link_server_log_result(pv_link_server_t *srv, pitvol_Result *r) {
  r->id = 0;
  if (!srv->cfg.log) return PV_LOG_OK;
  const uint32_t id = pv_log_last_seq(srv->cfg.log) + 1;
  r->id = id;
  uint8_t buf[pitvol_Result_size];
  pb_ostream_t os = pb_ostream_from_buffer(buf, sizeof buf);
  uint32_t seq = 0;
  pv_log_status_t st = PV_LOG_ERR_TOO_LARGE;
  if (pb_encode(&os, pitvol_Result_fields, r)) st = pv_log_append(srv->cfg.log, buf, os.bytes_written, &seq);
  if (st == PV_LOG_OK && seq != id) st = PV_LOG_ERR_CORRUPT; /* the log numbered it otherwise */
  if (st != PV_LOG_OK) r->id = 0;
  return st;
}

void pv_link_server_send_result(pv_link_server_t *srv, const pitvol_Result *r,
                                pv_log_status_t logged) {
  if (logged != PV_LOG_OK) {
    send_error(srv, PV_LINK_SERVER_ERR_LOG, "PV_BOARD_LOG", pv_log_status_message(logged));
  }
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_result_tag;
  m.body.result = *r;
  send_reliable(srv, &m);
  if (r->status != PV_OK) {
    const pv_status_t st = (pv_status_t)r->status;
    send_error(srv, r->status, pv_status_name(st), pv_status_message(st));
  }
  pv_link_server_send_status(srv);
}
