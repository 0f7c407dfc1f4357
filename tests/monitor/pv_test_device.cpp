// pv-test-device: a stand-in for the board on the host, for testing
// pitvol-monitor end to end. It runs the board's link server
// (lib/link/link_server.c: commands, result log fetch, results, status)
// over the real serial driver (drivers/serial, on the master side of a
// pseudo-terminal), result log (drivers/storage), density (lib/density) and,
// with --scan, the core measuring a scan file; only the application behind
// the server is fake: the board's state machine is replaced by the few
// callbacks below.
//
//   pv-test-device --log DIR --port-link PATH [--preload N] [--scan FILE]
//                  [--noise PERCENT] [--seed S] [--max-dry KG_M3] [--seconds S]
//                  [--lose-id ID] [--clock UNIX_S] [--hostile]
//
// PATH becomes a symlink to the pty's slave side: the monitor's PORT.
// --noise: that share of the bytes, both directions, is flipped, dropped or
// preceded by a random byte (line noise). --lose-id: that preloaded record is
// written as a payload that does not decode (damaged storage: the server
// skips it). --hostile: the strings it sends (device id, method, its
// refusals of StartScan and StopScan) carry terminal control sequences, as a
// broken or malicious board might.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "pitvol/density.h"
#include "pitvol/link.h"
#include "pitvol/link_result.h"
#include "pitvol/link_server.h"
#include "pitvol/pitvol.h"
#include "pitvol/result_log.h"
#include "pitvol/serial.h"
#include "scanio/scan_reader.h"
#include "test_rng.h"

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
  pv_log_t log;
  pv_link_server_t srv;
  Noise tx_noise, rx_noise;
  std::vector<uint8_t> wire_out;  // bytes on their way to the pty (after noise)

  pitvol_DeviceState state = pitvol_DeviceState_STATE_IDLE;
  uint64_t points = 0;
  bool mass_set = false, moisture_set = false;
  double mass_g = 0, moisture_percent = 0;
  pv_link_record_t record{};  // SetRecord; max dry density from --max-dry
};

long write_cb(void *ctx, const uint8_t *data, size_t len) {
  Device *d = static_cast<Device *>(ctx);
  if (d->wire_out.size() > 4096) return 0;  // backpressure, as a full UART FIFO
  d->tx_noise.apply(data, len, &d->wire_out);
  return long(len);
}

// The application behind the link server: the fake state above.

void app_status(void *ctx, pitvol_Status *s) {
  const Device &d = *static_cast<Device *>(ctx);
  s->state = d.state;
  s->points = d.points;
  s->mass_set = d.mass_set;
  s->mass_g = d.mass_set ? d.mass_g : 0;
  s->moisture_set = d.moisture_set;
  s->moisture_percent = d.moisture_set ? d.moisture_percent : 0;
}

pitvol_NackCode refuse(const Device &d, const char *reason, char *why, size_t cap) {
  std::snprintf(why, cap, "%s%s", d.opt.hostile ? kHostile : "", reason);
  return pitvol_NackCode_NACK_WRONG_STATE;
}

pitvol_NackCode app_start_scan(void *ctx, char *why, size_t cap) {
  Device &d = *static_cast<Device *>(ctx);
  if (d.state == pitvol_DeviceState_STATE_SCANNING)
    return refuse(d, "a scan is already running; stop it first", why, cap);
  d.state = pitvol_DeviceState_STATE_SCANNING;
  d.points = 0;
  return pitvol_NackCode_NACK_NONE;
}

// Answered now; the main loop computes once the answer is out (finish()
// takes a while).
pitvol_NackCode app_stop_scan(void *ctx, char *why, size_t cap) {
  Device &d = *static_cast<Device *>(ctx);
  if (d.state != pitvol_DeviceState_STATE_SCANNING)
    return refuse(d, "no scan is running; start one first", why, cap);
  d.state = pitvol_DeviceState_STATE_COMPUTING;
  return pitvol_NackCode_NACK_NONE;
}

void app_set_density_input(void *ctx, pv_input_kind_t kind, double v) {
  Device &d = *static_cast<Device *>(ctx);
  const bool moisture = kind == PV_INPUT_MOISTURE_PERCENT;
  (moisture ? d.moisture_set : d.mass_set) = true;
  (moisture ? d.moisture_percent : d.mass_g) = v;
}

void app_get_record(void *ctx, pv_link_record_t *out) { *out = static_cast<Device *>(ctx)->record; }
void app_set_record(void *ctx, const pv_link_record_t *rec) { static_cast<Device *>(ctx)->record = *rec; }

const pv_link_app_t kApp = {app_status,     app_start_scan, app_stop_scan, app_set_density_input,
                            app_get_record, app_set_record, nullptr};

// The result's message, made by the board's mapping, logged (its id is the
// record number). A fixed clock (deterministic logs): result id at
// --clock + 60 s x id.
pitvol_Result log_result(Device &d, const pv_result_t &r, const char *method, pv_log_status_t *st) {
  pv_density_t den{};
  if (r.status == PV_OK && d.mass_set) {
    pv_density_input_t in{};
    in.volume_cm3 = r.volume_cm3;
    in.interval_cm3 = r.interval_cm3;
    in.has_mass = 1;
    in.mass_g = d.mass_g;
    in.has_moisture = d.moisture_set;
    in.moisture_percent = d.moisture_percent;
    in.reference_max_dry_kg_m3 = d.record.max_dry_density_kg_m3;
    if (pv_density_compute(&in, &den) != PV_DENSITY_OK) den = pv_density_t{};
  }
  const int64_t clock = d.opt.clock + int64_t(pv_log_last_seq(&d.log) + 1) * 60;
  const pv_link_result_source_t src = {r.status,  &r,         d.opt.hostile ? "po\x1b[8mlar" : method,
                                       clock,     &den,       d.mass_g,
                                       d.moisture_percent, &d.record};
  pitvol_Result out;
  pv_link_result_message(&out, &src);
  if (r.status == PV_OK) d.record.test_id[0] = '\0';  // used up by a measured result, as on the board
  *st = pv_link_server_log_result(&d.srv, &out);
  if (*st != PV_LOG_OK) std::fprintf(stderr, "pv-test-device: %s\n", pv_log_status_message(*st));
  return out;
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

// The scan was stopped: measure, log and send the Result (and an Error if
// there is no volume), as the board does.
void finish_scan(Device &d) {
  std::string method = "polar";
  const pv_result_t r = d.opt.scan.empty() ? synthetic(pv_log_last_seq(&d.log) + 1)
                                           : measure_scan(d.opt.scan, &method);
  pv_log_status_t st = PV_LOG_OK;
  const pitvol_Result res = log_result(d, r, method.c_str(), &st);
  d.state = pitvol_DeviceState_STATE_RESULT;
  pv_link_server_send_result(&d.srv, &res, st);
}

// A record of --lose-id: damaged storage, a payload that is no pitvol.Result
// (a varint longer than 10 bytes).
bool log_damaged(Device &d) {
  const uint8_t junk[11] = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
  uint32_t seq = 0;
  return pv_log_append(&d.log, junk, sizeof junk, &seq) == PV_LOG_OK;
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
  const pv_link_server_config_t sc = {&kApp, &d, &d.log, d.opt.hostile ? kHostile : "PV-TEST-0001",
                                      pitvol_Capability_CAP_DENSITY, 0};
  pv_link_server_init(&d.srv, &sc);
  for (long i = 0; i < d.opt.preload && pv_log_last_seq(&d.log) < uint32_t(d.opt.preload); ++i) {
    if (pv_log_last_seq(&d.log) + 1 == d.opt.lose_id) {
      if (!log_damaged(d)) return 1;
      continue;
    }
    // Every third preloaded result with a mass and moisture set.
    d.mass_set = d.moisture_set = (i % 3 == 2);
    d.mass_g = 3000.0;
    d.moisture_percent = 12.5;
    pv_log_status_t st = PV_LOG_OK;
    (void)log_result(d, synthetic(pv_log_last_seq(&d.log) + 1), "polar", &st);
    if (st != PV_LOG_OK) return 1;
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
      pv_link_server_send_status(&d.srv);
      next_status = now + std::chrono::milliseconds(100);
    }
    const pv_link_status_t fst = pv_link_server_service(&d.srv, write_cb, &d);
    if (fst != PV_LINK_OK) {
      std::fprintf(stderr, "pv-test-device: %s\n", pv_link_status_message(fst));
      return 1;
    }
    if (d.state == pitvol_DeviceState_STATE_COMPUTING && !pv_link_server_busy(&d.srv) &&
        d.wire_out.empty())
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
      pv_link_server_feed(&d.srv, in.data(), in.size());
    }
  }
  std::fprintf(stderr, "pv-test-device: %u frames received, %u corrupt, %u repeated commands\n",
               d.srv.link.stats.frames_received, d.srv.link.stats.frames_corrupt,
               d.srv.link.stats.commands_duplicate);
  unlink(d.opt.port_link.c_str());
  pv_serial_close(&d.port);
  close(slave);
  pv_log_close(&d.log);
  return 0;
}
