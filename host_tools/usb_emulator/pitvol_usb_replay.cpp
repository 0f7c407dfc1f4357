// pitvol-usb-replay: replays a .frames file through an emulated USB scanner
// (umockdev) and the REAL libusb driver into a core session, and prints the
// volume like `pitvol measure` plus the driver's and the emulator's counters.
//
//   pitvol-usb-replay FILE.frames [--json] [--bench] [faults...]
//     --corrupt RATE     flip the CRC of this share of frames
//     --drop RATE        leave out this share of frames
//     --duplicate RATE   send this share of frames twice
//     --seed S           for the three above and --short-reads
//     --stall-at-frame N / --stall-at-byte B   halt the endpoint once
//     --short-reads      URBs return a random 1..len bytes
//     --unplug-at-frame N  unplug half way through frame N ...
//     --replug-after MS    ... and plug back after MS (default 200)
//     --fps F            pace the device to F average frames per second
//     --timeout S        give up after S seconds (default 60)
//
// Must run under umockdev-wrapper; if it is not, it re-runs itself there.
// Exit codes as pitvol: 0 measured, 2 usage, 3 input/USB failure,
// 4 no measurement, 5 internal error.
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "pitvol/result_report.h"
#include "pitvol/pitvol.h"
#include "pitvol/usb_scanner.h"
#include "usb_emulator/emulated_scanner.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Sink {
  pv_session_t *session = nullptr;
  uint64_t points = 0;
  pv_status_t push_status = PV_OK;  // the first push the session refused
};

void on_points(void *user, const pv_usb_frame_header_t *, const pv_point_t *pts, size_t n) {
  auto *s = static_cast<Sink *>(user);
  s->points += n;
  const pv_status_t st = pv_session_push(s->session, pts, n);
  if (st != PV_OK && s->push_status == PV_OK) s->push_status = st;
}

// A number option's value must be finite (CLI11's ranges let NaN pass).
const CLI::Validator kFinite(
    [](const std::string &v) {
      double d = 0;
      return CLI::detail::lexical_cast(v, d) && std::isfinite(d) ? std::string() : "not a finite number: " + v;
    },
    "");

const char *state_name(pv_usb_state_t st) {
  switch (st) {
    case PV_USB_STATE_IDLE: return "idle";
    case PV_USB_STATE_STREAMING: return "streaming";
    case PV_USB_STATE_ENDED: return "ended";
    case PV_USB_STATE_UNPLUGGED: return "unplugged";
  }
  return "?";
}

struct SessionBlock {
  void *ptr = nullptr;
  ~SessionBlock() { std::free(ptr); }
};

}  // namespace

int main(int argc, char **argv) {
  std::string path;
  bool json = false, bench = false;
  double fps = 0, timeout_s = 60;
  pv_emu_options_t eo;
  pv_emu_options_default(&eo);
  bool short_reads = false;

  // The command line (CLI11, as pitvol's); errors one line, exit 2.
  CLI::App app{"Replays a .frames file through the emulated USB scanner (umockdev) into the measuring "
               "core; runs itself under umockdev-wrapper.",
               "pitvol-usb-replay"};
  app.get_formatter()->label("Usage", "usage");
  app.footer("exit codes as pitvol: 0 measured, 2 usage, 3 input/USB failure, 4 no measurement,\n"
             "            5 internal error");
  app.add_option("FILE", path, "a .frames file (pitvol-sim --frames)")->required()->type_name("FILE.frames");
  app.add_flag("--json", json, "one JSON object on stdout");
  app.add_flag("--bench", bench, "also points/s and MB/s");
  app.add_option("--corrupt", eo.corrupt_rate, "flip the CRC of this share of frames")->type_name("RATE")->check(kFinite & CLI::Range(0.0, 1.0).description("0 .. 1"));
  app.add_option("--drop", eo.drop_rate, "leave out this share of frames")->type_name("RATE")->check(kFinite & CLI::Range(0.0, 1.0).description("0 .. 1"));
  app.add_option("--duplicate", eo.duplicate_rate, "send this share of frames twice")
      ->type_name("RATE")->check(kFinite & CLI::Range(0.0, 1.0).description("0 .. 1"));
  app.add_option("--seed", eo.seed, "seed for the three above and --short-reads")->type_name("S");
  app.add_option("--stall-at-frame", eo.stall_at_frame, "halt the endpoint once at frame N")
      ->type_name("N")->check(CLI::NonNegativeNumber);
  app.add_option("--stall-at-byte", eo.stall_at_byte, "halt the endpoint once at byte B")
      ->type_name("B")->check(CLI::NonNegativeNumber);
  app.add_flag("--short-reads", short_reads, "URBs return a random 1..len bytes");
  app.add_option("--unplug-at-frame", eo.unplug_at_frame, "unplug half way through frame N ...")
      ->type_name("N")->check(CLI::NonNegativeNumber);
  app.add_option("--replug-after", eo.replug_after_ms, "... and plug back after MS (default 200)")
      ->type_name("MS")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--fps", fps, "pace the device to F average frames per second (default: full speed)")
      ->type_name("F")
      ->check(kFinite & CLI::Validator(
                            [](const std::string &v) {
                              const double f = std::strtod(v.c_str(), nullptr);
                              return f > 0 && f <= 10000 ? std::string() : v + " is not in 0 < F <= 10000";
                            },
                            "0 < F <= 10000"));
  app.add_option("--timeout", timeout_s, "give up after S seconds (default 60)")
      ->type_name("S")
      ->check(kFinite & CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp &e) {
    return app.exit(e);
  } catch (const CLI::ParseError &e) {
    std::fprintf(stderr, "pitvol-usb-replay: %s (pitvol-usb-replay --help lists the options)\n", e.what());
    return 2;
  }
  eo.short_reads = short_reads ? 1 : 0;

  if (!pv_emu_available() && std::getenv("PITVOL_USB_REPLAY_NO_REEXEC") == nullptr) {
    // The emulator needs libumockdev-preload: run again under the wrapper.
    setenv("PITVOL_USB_REPLAY_NO_REEXEC", "1", 1);
    std::vector<char *> args;
    args.push_back(const_cast<char *>("umockdev-wrapper"));
    for (int i = 0; i < argc; ++i) args.push_back(argv[i]);
    args.push_back(nullptr);
    execvp("umockdev-wrapper", args.data());
    std::fprintf(stderr, "pitvol-usb-replay: cannot run umockdev-wrapper (%s); install umockdev\n",
                 std::strerror(errno));
    return 3;
  }

  char err[512] = "";
  pv_emu_t *emu = nullptr;
  if (fps > 0) {
    // Average frame size of the file paces the device at fps frames/s.
    pv_emu_t *probe = nullptr;
    pv_emu_options_t po;
    pv_emu_options_default(&po);
    if (pv_emu_create_from_file(&probe, path.c_str(), &po, err, sizeof err) != 0) {
      std::fprintf(stderr, "pitvol-usb-replay: %s: %s\n", path.c_str(), err);
      return 3;
    }
    pv_emu_stats_t ps;
    pv_emu_stats(probe, &ps);
    pv_emu_destroy(probe);
    eo.interval_ms = 10;
    eo.bytes_per_interval =
        uint32_t(std::ceil(double(ps.bytes_out) / double(ps.frames_out) * fps / 100.0));
  }
  if (pv_emu_create_from_file(&emu, path.c_str(), &eo, err, sizeof err) != 0) {
    std::fprintf(stderr, "pitvol-usb-replay: %s: %s\n", path.c_str(), err);
    return 3;
  }

  pv_config_t cfg;
  pv_config_default(&cfg);
  size_t bytes = 0;
  const pv_status_t size_st = pv_session_size(&cfg, &bytes);
  if (size_st != PV_OK) {
    std::fprintf(stderr, "pitvol-usb-replay: the default configuration has no block size: %s\n",
                 pv_status_message(size_st));
    pv_emu_destroy(emu);
    return 5;
  }
  SessionBlock block;
  block.ptr = std::aligned_alloc(PV_BLOCK_ALIGN, (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN);
  Sink sink;
  if (block.ptr == nullptr || pv_session_init(&cfg, block.ptr, bytes, &sink.session) != PV_OK) {
    std::fprintf(stderr, "pitvol-usb-replay: cannot set up a session of %zu bytes\n", bytes);
    pv_emu_destroy(emu);
    return 5;
  }

  const auto t0 = Clock::now();
  pv_usb_scanner_t *sc = nullptr;
  pv_usb_status_t ust = pv_usb_scanner_open(&sc, on_points, &sink);
  if (ust == PV_USB_OK) ust = pv_usb_scanner_start(sc);
  if (ust != PV_USB_OK) {
    std::fprintf(stderr, "pitvol-usb-replay: %s\n", pv_usb_status_message(ust));
    pv_usb_scanner_close(sc);
    pv_emu_destroy(emu);
    return 3;
  }
  const auto t_start = Clock::now();
  pv_usb_state_t state = PV_USB_STATE_STREAMING;
  bool timed_out = false;
  while (state != PV_USB_STATE_ENDED) {
    state = pv_usb_scanner_poll(sc, 100);
    if (std::chrono::duration<double>(Clock::now() - t0).count() > timeout_s) {
      timed_out = true;
      break;
    }
  }
  const double stream_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  pv_usb_scanner_stats_t us;
  pv_usb_scanner_get_stats(sc, &us);
  pv_usb_scanner_close(sc);
  pv_emu_stats_t es;
  pv_emu_stats(emu, &es);
  pv_emu_destroy(emu);
  // Bad points are counted, not refused: a refused push is a bug of this
  // program, and the volume would be of part of the scan.
  if (sink.push_status != PV_OK) {
    std::fprintf(stderr, "pitvol-usb-replay: the session refused points: %s (%s)\n",
                 pv_status_message(sink.push_status), pv_status_name(sink.push_status));
    return 5;
  }

  const auto t_finish = Clock::now();
  pv_result_t r{};
  const pv_status_t st = pv_session_finish(sink.session, &r);
  const double finish_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_finish).count();
  const bool ok = st == PV_OK && !timed_out;
  const double pts_per_s = stream_s > 0 ? double(us.stream.points_ok) / stream_s : 0;
  const double mb_per_s = stream_s > 0 ? double(us.stream.bytes_in) / stream_s / 1e6 : 0;

  if (json) {
    using pv::tools::Json;
    const Json usb = {{"state", state_name(state)},
                      {"bytes_in", us.stream.bytes_in},
                      {"bytes_skipped", us.stream.bytes_skipped},
                      {"headers_bad", us.stream.headers_bad},
                      {"frames_ok", us.stream.frames_ok},
                      {"frames_bad_crc", us.stream.frames_bad_crc},
                      {"frames_duplicate", us.stream.frames_duplicate},
                      {"sequence_gaps", us.stream.sequence_gaps},
                      {"frames_lost", us.stream.frames_lost},
                      {"points_ok", us.stream.points_ok},
                      {"points_nonfinite", us.stream.points_nonfinite},
                      {"points_out_of_range", us.stream.points_out_of_range},
                      {"scans_ended", us.stream.scans_ended},
                      {"transfers_completed", us.transfers_completed},
                      {"transfers_short", us.transfers_short},
                      {"stalls_cleared", us.stalls_cleared},
                      {"timeouts", us.timeouts},
                      {"transfer_errors", us.transfer_errors},
                      {"unplugs", us.unplugs},
                      {"replugs", us.replugs}};
    const Json emulator = {{"frames_in", es.frames_in},
                           {"frames_out", es.frames_out},
                           {"frames_corrupted", es.frames_corrupted},
                           {"frames_dropped", es.frames_dropped},
                           {"frames_duplicated", es.frames_duplicated},
                           {"bytes_served", es.bytes_served},
                           {"clear_halts", es.clear_halts},
                           {"unplugs", es.unplugs},
                           {"replugs", es.replugs}};
    Json o = {{"pitvol_version", PV_VERSION_STRING},
              {"method", pv_method_name(cfg.method)},
              {"file", path},
              {"status", timed_out ? "PV_ERR_USB_TIMEOUT" : pv_status_name(st)},
              {"message", timed_out ? "the scan did not end in time" : pv_status_message(st)}};
    pv::tools::add_result_fields(&o, r, ok);
    o["usb"] = usb;
    o["emulator"] = emulator;
    o["timings_ms"] = {{"stream", stream_s * 1000.0}, {"finish", finish_ms}};
    if (bench) {
      o["points_per_s"] = pts_per_s;
      o["mb_per_s"] = mb_per_s;
    }
    std::printf("%s\n", pv::tools::json_line(o).c_str());
  } else {
    if (ok) pv::tools::print_result_summary(stdout, r, cfg.method);
    std::printf("usb state      %s\n", state_name(state));
    std::printf("usb frames     %llu ok, %llu bad crc, %llu duplicate, %llu lost in %llu gaps\n",
                (unsigned long long)us.stream.frames_ok, (unsigned long long)us.stream.frames_bad_crc,
                (unsigned long long)us.stream.frames_duplicate, (unsigned long long)us.stream.frames_lost,
                (unsigned long long)us.stream.sequence_gaps);
    std::printf("usb bytes      %llu in, %llu skipped, %llu bad headers\n",
                (unsigned long long)us.stream.bytes_in, (unsigned long long)us.stream.bytes_skipped,
                (unsigned long long)us.stream.headers_bad);
    std::printf("usb transfers  %llu completed (%llu short), %llu stalls cleared, %llu timeouts, %llu errors\n",
                (unsigned long long)us.transfers_completed, (unsigned long long)us.transfers_short,
                (unsigned long long)us.stalls_cleared, (unsigned long long)us.timeouts,
                (unsigned long long)us.transfer_errors);
    std::printf("usb plug       %llu unplugs, %llu replugs\n", (unsigned long long)us.unplugs,
                (unsigned long long)us.replugs);
    std::printf("emulator       %llu frames (%llu corrupted, %llu dropped, %llu duplicated), %llu bytes served\n",
                (unsigned long long)es.frames_out, (unsigned long long)es.frames_corrupted,
                (unsigned long long)es.frames_dropped, (unsigned long long)es.frames_duplicated,
                (unsigned long long)es.bytes_served);
    if (bench) {
      std::printf("bench          %.0f points/s, %.1f MB/s (%llu points in %.3f s)\n", pts_per_s,
                  mb_per_s, (unsigned long long)us.stream.points_ok, stream_s);
    }
  }
  if (timed_out) {
    std::fprintf(stderr, "pitvol-usb-replay: the scan did not end within %.0f s (state %s)\n", timeout_s,
                 state_name(state));
    return 3;
  }
  if (st != PV_OK) {
    pv::tools::print_refusal(stderr, "pitvol-usb-replay", st, r);
    return (st == PV_ERR_INTERNAL || st == PV_ERR_OUT_OF_MEMORY) ? 5 : 4;
  }
  return 0;
}
