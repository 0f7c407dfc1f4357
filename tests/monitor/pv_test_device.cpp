// pv-test-device: a stand-in for the board application on the host, for
// testing pitvol-monitor end to end before the board app exists. It is the
// real serial stack -- link layer (lib/link), serial driver
// (drivers/serial, on the master side of a pseudo-terminal), result log
// (drivers/storage), density (lib/density) and, with --scan, the core
// measuring a scan file -- with the board's state machine replaced by the
// few lines below. The board application calls the same APIs.
//
//   pv-test-device --log DIR --port-link PATH [--preload N] [--scan FILE]
//                  [--noise PERCENT] [--seed S] [--max-dry KG_M3] [--seconds S]
//                  [--lose-id ID] [--clock UNIX_S] [--hostile]
//
// PATH becomes a symlink to the pty's slave side: the monitor's PORT.
// --noise: that share of the bytes, both directions, is flipped, dropped or
// preceded by a random byte (line noise). --lose-id: the log acts as if that
// record were damaged (GetResults skips it). --hostile: the strings it sends
// (device id, method, refusals, errors) carry terminal control sequences,
// as a broken or malicious board might.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <pb_decode.h>
#include <pb_encode.h>

#include "board_clock.h"
#include "board_record.h"
#include "board_refusal.h"
#include "pitvol/density.h"
#include "pitvol/user_input.h"
#include "pitvol/link.h"
#include "pitvol/pitvol.h"
#include "pitvol/result_log.h"
#include "pitvol/serial.h"
#include "scanio/scan_reader.h"
#include "test_rng.h"

static_assert(PV_DENSITY_WET == pitvol_DensityFlag_DENSITY_WET, "density flags = protocol flags");
static_assert(PV_DENSITY_DRY == pitvol_DensityFlag_DENSITY_DRY, "density flags = protocol flags");
static_assert(PV_DENSITY_COMPACTION == pitvol_DensityFlag_DENSITY_COMPACTION, "density flags");
static_assert(PV_DENSITY_UNBOUNDED == pitvol_DensityFlag_DENSITY_UNBOUNDED, "density flags");

namespace {

using Clock = std::chrono::steady_clock;
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

struct Options {
  std::string log_dir, port_link, scan;
  long preload = 0;
  uint32_t lose_id = 0;  // acts as if this record were damaged: never sent
  int64_t clock = 1790000000;  // the board clock's reading at result 0 (0: never set)
  double noise_percent = 0, max_dry = 1850.0, seconds = 600;
  uint64_t seed = 1;
  bool hostile = false;
};

// Clears the screen, retitles the window, rings the bell, an 8-bit CSI
// (0x9b) and its UTF-8 form (U+009B), a stray byte that is not UTF-8.
const char kHostile[] = "\x1b[2J\x1b]0;owned\x07\x9b" "31m\xc2\x9b" "1m\xff";

// Line noise on a byte stream.
struct Noise {
  double p = 0;
  pv::test::Rng rng{1};
  void apply(const uint8_t *in, size_t n, std::vector<uint8_t> *out) {
    for (size_t i = 0; i < n; ++i) {
      if (p > 0 && rng.uniform() < p) {
        switch (rng.next() % 3) {
          case 0: out->push_back(uint8_t(in[i] ^ (1u << (rng.next() % 8)))); break;
          case 1: break;
          default: out->push_back(uint8_t(rng.next())); out->push_back(in[i]); break;
        }
      } else {
        out->push_back(in[i]);
      }
    }
  }
};

struct Device {
  Options opt;
  pv_serial_t port{-1, 0, 0};
  pv_link_t link;
  pv_log_t log;
  Noise tx_noise, rx_noise;
  std::vector<uint8_t> wire_out;  // bytes on their way to the pty (after noise)
  struct Out {
    pitvol_Message msg;
    bool is_reply = false;
    uint32_t reply_to = 0;
  };
  std::deque<Out> outbox;  // reliable messages waiting for queue room

  pitvol_DeviceState state = pitvol_DeviceState_STATE_IDLE;
  uint64_t points = 0;
  bool mass_set = false, moisture_set = false;
  double mass_g = 0, moisture_percent = 0;
  pv_board_record_t record{};  // SetRecord; max dry density from --max-dry

  struct Fetch {
    bool on = false;
    uint32_t cmd_seq = 0, to_id = 0, sent = 0;
    pv_log_cursor_t cur{};
  } fetch;
};

long write_cb(void *ctx, const uint8_t *data, size_t len) {
  Device *d = static_cast<Device *>(ctx);
  if (d->wire_out.size() > 4096) return 0;  // backpressure, as a full UART FIFO
  d->tx_noise.apply(data, len, &d->wire_out);
  return long(len);
}

void queue_reliable(Device &d, const pitvol_Message &m) {
  Device::Out o;
  o.msg = m;
  d.outbox.push_back(o);
}

void pump_outbox(Device &d) {
  while (!d.outbox.empty()) {
    const Device::Out &o = d.outbox.front();
    const pv_link_status_t st = o.is_reply ? pv_link_send_reply(&d.link, o.reply_to, &o.msg)
                                           : pv_link_send(&d.link, &o.msg, PV_LINK_RELIABLE, nullptr);
    if (st != PV_LINK_OK) return;
    d.outbox.pop_front();
  }
}

pitvol_Result make_result(Device &d, uint32_t id, const pv_result_t &r, const char *method) {
  pitvol_Result out = pitvol_Result_init_zero;
  out.id = id;
  // A fixed clock (deterministic logs) through the board's own rule: an
  // unset clock (--clock 0, 1970) gives time 0.
  out.time_unix_s = pv_board_result_time(d.opt.clock + int64_t(id) * 60);
  out.status = int32_t(r.status);
  std::snprintf(out.method, sizeof out.method, "%s", d.opt.hostile ? "po\x1b[8mlar" : method);
  out.volume_cm3 = r.volume_cm3;
  out.interval_cm3 = r.interval_cm3;
  out.depth_mm = r.depth_mm;
  out.warnings = r.warnings;
  out.unseen_share = r.unseen_share;
  out.points_in = r.points_in;
  out.points_used = r.points_used;
  pv_board_result_refusal(&out, r.status, &r);
  if (r.status == PV_OK) {
    pv_density_input_t in{};
    in.volume_cm3 = r.volume_cm3;
    in.interval_cm3 = r.interval_cm3;
    in.has_mass = d.mass_set;
    in.mass_g = d.mass_g;
    in.has_moisture = d.moisture_set;
    in.moisture_percent = d.moisture_percent;
    in.reference_max_dry_kg_m3 = d.record.max_dry_density_kg_m3;
    pv_density_t den;
    if (pv_density_compute(&in, &den) == PV_DENSITY_OK && den.flags) {
      out.has_density = true;
      pitvol_Density &p = out.density;
      p.flags = den.flags;
      p.mass_g = d.mass_g;
      p.moisture_percent = d.moisture_set ? d.moisture_percent : 0;
      p.wet_kg_m3 = den.wet_kg_m3;
      p.wet_low_kg_m3 = den.wet_low_kg_m3;
      p.wet_high_kg_m3 = den.wet_high_kg_m3;
      p.dry_kg_m3 = den.dry_kg_m3;
      p.dry_low_kg_m3 = den.dry_low_kg_m3;
      p.dry_high_kg_m3 = den.dry_high_kg_m3;
      p.reference_max_dry_kg_m3 = (den.flags & PV_DENSITY_COMPACTION) ? d.record.max_dry_density_kg_m3 : 0;
      p.compaction_percent = den.compaction_percent;
      p.compaction_low_percent = den.compaction_low_percent;
      p.compaction_high_percent = den.compaction_high_percent;
    }
    pv_board_result_record(&out, &d.record, &den, r.volume_cm3);
    d.record.test_id[0] = '\0';  // used up by a measured result, as on the board
  }
  return out;
}

// Appends a result to the log (its id is the record number) and returns it.
bool log_result(Device &d, const pv_result_t &r, const char *method, pitvol_Result *out) {
  const uint32_t id = pv_log_last_seq(&d.log) + 1;
  *out = make_result(d, id, r, method);
  uint8_t buf[pitvol_Result_size];
  pb_ostream_t os = pb_ostream_from_buffer(buf, sizeof buf);
  if (!pb_encode(&os, pitvol_Result_fields, out)) return false;
  uint32_t seq = 0;
  const pv_log_status_t st = pv_log_append(&d.log, buf, os.bytes_written, &seq);
  if (st != PV_LOG_OK || seq != id) {
    std::fprintf(stderr, "pv-test-device: %s\n", pv_log_status_message(st));
    return false;
  }
  return true;
}

pv_result_t synthetic(uint32_t id) {
  pv_result_t r{};
  r.status = PV_OK;
  r.volume_cm3 = 1500.0 + 1.25 * (id - 1);
  r.interval_cm3 = 30.0;
  r.depth_mm = 150.0;
  r.points_in = 100000 + id;
  r.points_used = 90000 + id;
  // As a surface scan's: thinned always (a note), on even ids 3 % of the
  // volume over bridged wall (a warning).
  r.warnings = PV_WARN_POINTS_THINNED | (id % 2 == 0 ? PV_WARN_BRIDGED : 0u);
  r.unseen_share = id % 2 == 0 ? 0.03 : 0.002;
  return r;
}

// The core on the --scan file, as `pitvol measure FILE` does it.
pv_result_t measure_scan(const std::string &path, std::string *method) {
  pv_result_t r{};
  r.status = PV_ERR_INTERNAL;
  pv_config_t cfg;
  pv_config_default(&cfg);
  *method = pv_method_name(cfg.method);
  size_t bytes = 0;
  if (pv_session_size(&cfg, &bytes) != PV_OK) return r;
  const size_t rounded = (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
  std::unique_ptr<void, decltype(&std::free)> block(std::aligned_alloc(PV_BLOCK_ALIGN, rounded), &std::free);
  pv_session_t *s = nullptr;
  if (!block || pv_session_init(&cfg, block.get(), bytes, &s) != PV_OK) return r;
  pv::scanio::Error err;
  auto reader = pv::scanio::open_scan(path, pv::scanio::Format::Auto, &err);
  if (!reader) return r;
  std::vector<pv_point_t> chunk(65536);
  long n;
  while ((n = reader->read(chunk.data(), chunk.size(), &err)) > 0) {
    if (pv_session_push(s, chunk.data(), size_t(n)) != PV_OK) return r;
  }
  // finish fills r, its status included; a call it refuses leaves r.status
  // at PV_ERR_INTERNAL.
  (void)pv_session_finish(s, &r);
  return r;
}

void send_hello(Device &d) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_hello_tag;
  pitvol_Hello &h = m.body.hello;
  h.protocol_version = PV_LINK_PROTOCOL_VERSION;
  std::snprintf(h.firmware_version, sizeof h.firmware_version, "%s", PV_VERSION_STRING);
  std::snprintf(h.device_id, sizeof h.device_id, "%s", d.opt.hostile ? kHostile : "PV-TEST-0001");
  h.capabilities = pitvol_Capability_CAP_RESULT_LOG | pitvol_Capability_CAP_DENSITY;
  h.max_frame_bytes = PV_LINK_MAX_WIRE_BYTES;
  h.first_result_id = pv_log_first_seq(&d.log);
  h.last_result_id = pv_log_last_seq(&d.log);
  queue_reliable(d, m);
}

void send_status(Device &d) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_status_tag;
  pitvol_Status &s = m.body.status;
  s.state = d.state;
  s.points = d.points;
  s.last_result_id = pv_log_last_seq(&d.log);
  s.mass_set = d.mass_set;
  s.mass_g = d.mass_g;
  s.moisture_set = d.moisture_set;
  s.moisture_percent = d.moisture_percent;
  s.frames_corrupt = d.link.stats.frames_corrupt;
  // A full queue drops a Status (counted in lossy_dropped): the next replaces it.
  (void)pv_link_send(&d.link, &m, PV_LINK_LOSSY, nullptr);
}

// Replies wait in the outbox behind the messages the command produced
// (Hello, Result), and go out through pv_link_send_reply so that the link
// answers a repeated command with them.
void reply(Device &d, const pitvol_Message &m) {
  Device::Out o;
  o.msg = m;
  o.reply_to = m.which_body == pitvol_Message_ack_tag ? m.body.ack.command_seq : m.body.nack.command_seq;
  o.is_reply = true;
  d.outbox.push_back(o);
  pump_outbox(d);
}

void ack(Device &d, uint32_t seq, uint32_t sent = 0) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_ack_tag;
  m.body.ack = {seq, pv_log_first_seq(&d.log), pv_log_last_seq(&d.log), sent};
  reply(d, m);
}

void nack(Device &d, uint32_t seq, pitvol_NackCode code, const char *reason) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = pitvol_Message_nack_tag;
  m.body.nack.command_seq = seq;
  m.body.nack.code = code;
  std::snprintf(m.body.nack.reason, sizeof m.body.nack.reason, "%s%s", d.opt.hostile ? kHostile : "", reason);
  reply(d, m);
}

// The scan was stopped: measure, log, send the Result (and an Error if
// there is no volume).
void finish_scan(Device &d) {
  std::string method = "polar";
  const pv_result_t r = d.opt.scan.empty() ? synthetic(pv_log_last_seq(&d.log) + 1)
                                           : measure_scan(d.opt.scan, &method);
  pitvol_Result res;
  if (!log_result(d, r, method.c_str(), &res)) {
    pitvol_Message e = pitvol_Message_init_zero;
    e.which_body = pitvol_Message_error_tag;
    e.body.error.code = 100;
    std::snprintf(e.body.error.name, sizeof e.body.error.name, "PV_BOARD_LOG");
    std::snprintf(e.body.error.message, sizeof e.body.error.message, "%s", pv_log_status_message(PV_LOG_ERR_IO));
    queue_reliable(d, e);
    d.state = pitvol_DeviceState_STATE_ERROR;
    return;
  }
  d.state = pitvol_DeviceState_STATE_RESULT;
  pitvol_Message out = pitvol_Message_init_zero;
  out.which_body = pitvol_Message_result_tag;
  out.body.result = res;
  queue_reliable(d, out);
  if (r.status != PV_OK) {
    pitvol_Message e = pitvol_Message_init_zero;
    e.which_body = pitvol_Message_error_tag;
    e.body.error.code = int32_t(r.status);
    std::snprintf(e.body.error.name, sizeof e.body.error.name, "%s", pv_status_name(r.status));
    std::snprintf(e.body.error.message, sizeof e.body.error.message, "%s%s", d.opt.hostile ? kHostile : "",
                  pv_status_message(r.status));
    queue_reliable(d, e);
  }
}

void handle(Device &d, const pv_link_rx_t &rx) {
  const pitvol_Message &m = rx.msg;
  switch (m.which_body) {
    case pitvol_Message_get_hello_tag:
      send_hello(d);
      ack(d, rx.seq);
      break;
    case pitvol_Message_start_scan_tag:
      if (d.state == pitvol_DeviceState_STATE_SCANNING) {
        nack(d, rx.seq, pitvol_NackCode_NACK_WRONG_STATE, "a scan is already running; stop it first");
        break;
      }
      d.state = pitvol_DeviceState_STATE_SCANNING;
      d.points = 0;
      ack(d, rx.seq);
      break;
    case pitvol_Message_stop_scan_tag:
      if (d.state != pitvol_DeviceState_STATE_SCANNING) {
        nack(d, rx.seq, pitvol_NackCode_NACK_WRONG_STATE, "no scan is running; start one first");
        break;
      }
      // Answer now, compute once the answer is out (finish() takes a while).
      d.state = pitvol_DeviceState_STATE_COMPUTING;
      ack(d, rx.seq);
      break;
    case pitvol_Message_set_mass_tag:
    case pitvol_Message_set_moisture_tag: {
      // As the board: the plausible ranges of pitvol/user_input.h.
      const bool moisture = m.which_body == pitvol_Message_set_moisture_tag;
      const double v = moisture ? m.body.set_moisture.moisture_percent : m.body.set_mass.mass_g;
      char why[sizeof(pitvol_Nack{}.reason)];
      if (pv_input_check(moisture ? PV_INPUT_MOISTURE_PERCENT : PV_INPUT_MASS_G, v, why, sizeof why) != 0) {
        nack(d, rx.seq, pitvol_NackCode_NACK_OUT_OF_RANGE, why);
        break;
      }
      (moisture ? d.moisture_set : d.mass_set) = true;
      (moisture ? d.moisture_percent : d.mass_g) = v;
      ack(d, rx.seq);
      break;
    }
    case pitvol_Message_set_record_tag: {
      char why[sizeof(pitvol_Nack{}.reason)];
      if (pv_board_record_apply(&d.record, &m.body.set_record, why, sizeof why) != 0) {
        nack(d, rx.seq, pitvol_NackCode_NACK_OUT_OF_RANGE, why);
        break;
      }
      ack(d, rx.seq);
      break;
    }
    case pitvol_Message_get_results_tag:
      if (d.fetch.on) ack(d, d.fetch.cmd_seq, d.fetch.sent);  // a newer request replaces it
      d.fetch = {};
      d.fetch.on = true;
      d.fetch.cmd_seq = rx.seq;
      d.fetch.to_id = m.body.get_results.to_id ? m.body.get_results.to_id : UINT32_MAX;
      if (pv_log_seek(&d.log, m.body.get_results.from_id, &d.fetch.cur) != PV_LOG_OK) {
        d.fetch.on = false;
        nack(d, rx.seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(PV_LOG_ERR_IO));
      }
      break;
    default:
      nack(d, rx.seq, pitvol_NackCode_NACK_UNKNOWN_COMMAND, "this board does not know that command");
      break;
  }
}

// Streams a GetResults answer as the link drains, so the queue stays bounded.
void continue_fetch(Device &d) {
  while (d.fetch.on && d.outbox.empty() && pv_link_tx_room(&d.link) > 2) {
    uint8_t buf[PV_LOG_MAX_PAYLOAD_BYTES];
    uint32_t seq = 0;
    size_t len = 0;
    const pv_log_status_t st = pv_log_next(&d.log, &d.fetch.cur, buf, sizeof buf, &seq, &len);
    if (st == PV_LOG_END || (st == PV_LOG_OK && seq > d.fetch.to_id)) {
      d.fetch.on = false;
      ack(d, d.fetch.cmd_seq, d.fetch.sent);
      return;
    }
    if (st != PV_LOG_OK) {
      d.fetch.on = false;
      nack(d, d.fetch.cmd_seq, pitvol_NackCode_NACK_STORAGE, pv_log_status_message(st));
      return;
    }
    if (seq == d.opt.lose_id) continue;
    pitvol_Message m = pitvol_Message_init_zero;
    m.which_body = pitvol_Message_result_tag;
    pb_istream_t is = pb_istream_from_buffer(buf, len);
    if (!pb_decode(&is, pitvol_Result_fields, &m.body.result)) continue;
    if (pv_link_send(&d.link, &m, PV_LINK_RELIABLE, nullptr) != PV_LINK_OK) return;
    d.fetch.sent++;
  }
}

int usage() {
  std::fprintf(stderr,
               "usage: pv-test-device --log DIR --port-link PATH [--preload N] [--scan FILE]\n"
               "                      [--noise PERCENT] [--seed S] [--max-dry KG_M3] [--seconds S]\n"
               "                      [--lose-id ID] [--clock UNIX_S] [--hostile]\n");
  return 2;
}

}  // namespace

int main(int argc, char **argv) {
  static Device d;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--hostile") {
      d.opt.hostile = true;
      continue;
    }
    if (i + 1 >= argc) return usage();
    const char *v = argv[++i];
    if (a == "--log") d.opt.log_dir = v;
    else if (a == "--port-link") d.opt.port_link = v;
    else if (a == "--scan") d.opt.scan = v;
    else if (a == "--preload") d.opt.preload = std::atol(v);
    else if (a == "--noise") d.opt.noise_percent = std::atof(v);
    else if (a == "--seed") d.opt.seed = std::strtoull(v, nullptr, 10);
    else if (a == "--max-dry") d.opt.max_dry = std::atof(v);
    else if (a == "--seconds") d.opt.seconds = std::atof(v);
    else if (a == "--lose-id") d.opt.lose_id = uint32_t(std::atol(v));
    else if (a == "--clock") d.opt.clock = std::strtoll(v, nullptr, 10);
    else return usage();
  }
  if (d.opt.log_dir.empty() || d.opt.port_link.empty()) return usage();
  d.record.max_dry_density_kg_m3 = d.opt.max_dry;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  pv_log_config_t cfg;
  pv_log_config_default(&cfg);
  pv_log_status_t lst = pv_log_open(&d.log, d.opt.log_dir.c_str(), &cfg);
  if (lst != PV_LOG_OK) {
    std::fprintf(stderr, "pv-test-device: %s\n", pv_log_status_message(lst));
    return 1;
  }
  for (long i = 0; i < d.opt.preload && pv_log_last_seq(&d.log) < uint32_t(d.opt.preload); ++i) {
    // Every third preloaded result with a mass and moisture set.
    d.mass_set = d.moisture_set = (i % 3 == 2);
    d.mass_g = 3000.0;
    d.moisture_percent = 12.5;
    pitvol_Result res;
    if (!log_result(d, synthetic(pv_log_last_seq(&d.log) + 1), "polar", &res)) return 1;
  }
  d.mass_set = d.moisture_set = false;

  int master = -1, slave = -1;
  char name[256];
  if (openpty(&master, &slave, name, nullptr, nullptr) != 0) {
    std::perror("pv-test-device: openpty");
    return 1;
  }
  // The slave stays open here too, so the master never sees a hangup
  // between two monitor runs.
  const pv_serial_status_t sst = pv_serial_adopt(&d.port, master, 115200);
  if (sst != PV_SERIAL_OK) {
    std::fprintf(stderr, "pv-test-device: %s\n", pv_serial_status_message(sst));
    return 1;
  }
  unlink(d.opt.port_link.c_str());
  if (symlink(name, d.opt.port_link.c_str()) != 0) {
    std::perror("pv-test-device: symlink");
    return 1;
  }
  pv_link_init(&d.link, 0);
  d.tx_noise.p = d.rx_noise.p = d.opt.noise_percent / 100.0;
  d.tx_noise.rng.s = d.opt.seed;
  d.rx_noise.rng.s = d.opt.seed * 7919u + 1u;
  std::printf("port %s\n", name);
  std::fflush(stdout);

  const auto start = Clock::now();
  auto next_status = Clock::now();
  while (!g_stop && std::chrono::duration<double>(Clock::now() - start).count() < d.opt.seconds) {
    const auto now = Clock::now();
    if (now >= next_status) {
      if (d.state == pitvol_DeviceState_STATE_SCANNING) d.points += 1000;
      send_status(d);
      next_status = now + std::chrono::milliseconds(100);
    }
    pump_outbox(d);
    continue_fetch(d);
    const pv_link_status_t fst = pv_link_tx_flush(&d.link, write_cb, &d);
    if (fst != PV_LINK_OK) {
      std::fprintf(stderr, "pv-test-device: %s\n", pv_link_status_message(fst));
      return 1;
    }
    if (d.state == pitvol_DeviceState_STATE_COMPUTING && d.outbox.empty() &&
        !pv_link_tx_pending(&d.link) && d.wire_out.empty())
      finish_scan(d);
    pollfd pfd{pv_serial_fd(&d.port), short(POLLIN | (d.wire_out.empty() ? 0 : POLLOUT)), 0};
    if (poll(&pfd, 1, 20) < 0) continue;
    if (pfd.revents & POLLOUT) {
      size_t w = 0;
      if (pv_serial_write(&d.port, d.wire_out.data(), d.wire_out.size(), &w) == PV_SERIAL_OK)
        d.wire_out.erase(d.wire_out.begin(), d.wire_out.begin() + long(w));
    }
    if (pfd.revents & POLLIN) {
      uint8_t buf[512];
      size_t n = 0;
      if (pv_serial_read(&d.port, buf, sizeof buf, &n) != PV_SERIAL_OK) continue;
      std::vector<uint8_t> in;
      d.rx_noise.apply(buf, n, &in);
      for (size_t at = 0; at < in.size();) {
        pv_link_rx_t rx;
        int got = 0;
        at += pv_link_feed(&d.link, in.data() + at, in.size() - at, &rx, &got);
        if (got) handle(d, rx);
      }
    }
  }
  std::fprintf(stderr, "pv-test-device: %u frames received, %u corrupt, %u repeated commands\n",
               d.link.stats.frames_received, d.link.stats.frames_corrupt, d.link.stats.commands_duplicate);
  unlink(d.opt.port_link.c_str());
  pv_serial_close(&d.port);
  close(slave);
  pv_log_close(&d.log);
  return 0;
}
