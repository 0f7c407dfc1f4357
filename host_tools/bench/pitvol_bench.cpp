// pitvol-bench: throughput and latency of the measuring core and the CLI.
//
//   pitvol-bench [--markdown] [--ingest-points N] [--scan-points N]
//                [--scale N,N,...] [--no-peers]
//
// Measures, on one thread (wall clock, and the thread's CPU time beside it:
// on a shared machine the CPU time is the steadier figure):
//   1. ingest rate of pv_session_push (points/s): N points of a synthetic
//      pit are generated into memory first (not timed), then only the push
//      calls, in batches of 4096, are timed; median of 5 runs, the session
//      is reset between runs;
//   2. pv_session_estimate() and pv_session_finish() latency (ms) for a
//      scan of M points, default method (surface), and finish() of the
//      paper's method: median of 9 / 5 / 5;
//   3. whole-file replay: the M-point scan written as binary PLY (the
//      format of pitvol-synth) to a temp file, then `pitvol measure FILE
//      --json` run end to end (the pitvol binary next to this program);
//      median of 3; where CloudCompare is installed, its 2.5D volume of the
//      same scan (levelled by pitvol, untimed; docs/accuracy.md "Peers")
//      timed the same way, side by side, with both volumes' errors;
//   4. scaling: for each size of --scale, a child process streams that many
//      points of a synthetic pit (generated on the fly, 4096 at a time)
//      and finishes: push time, finish time, its peak RSS and the volume;
//   5. memory: pv_session_size() for the default configuration, the peak
//      RSS of this process after the runs (it holds the N pre-generated
//      points) and the peak RSS of the pitvol CLI children.
// Times come from std::chrono::steady_clock and CLOCK_THREAD_CPUTIME_ID.
#include <fcntl.h>
#include <time.h>
#include <limits.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <limits>
#include <vector>

#include <CLI/CLI.hpp>

#include "pitvol/pitvol.h"
#include "synth/synthetic_pit.h"

extern char **environ;

namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kBatch = 4096;
constexpr int kIngestRuns = 5;
constexpr int kFinishRuns = 5;
constexpr int kReplayRuns = 3;
constexpr int kEstimateRuns = 9;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

double cpu_ms() {  // this thread's CPU time
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// Peak resident set of this process image (VmHWM: unlike ru_maxrss, it
// starts afresh at exec), KiB.
long vm_hwm_kib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::atol(line.c_str() + 6);
  }
  return -1;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  if (n == 0) return 0;
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    // x86: "model name"; some aarch64 kernels: "Model" or "Hardware".
    if (line.rfind("model name", 0) == 0 || line.rfind("Model", 0) == 0 ||
        line.rfind("Hardware", 0) == 0) {
      const size_t c = line.find(':');
      if (c != std::string::npos) {
        size_t b = c + 1;
        while (b < line.size() && line[b] == ' ') ++b;
        return line.substr(b);
      }
    }
  }
  return "unknown";
}

std::string self_dir() {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return ".";
  buf[n] = '\0';
  std::string p(buf);
  const size_t s = p.rfind('/');
  return s == std::string::npos ? "." : p.substr(0, s);
}

std::vector<pv_point_t> make_scan(size_t n, uint64_t seed) {
  pv::synth::PitSpec spec;
  spec.seed = seed;
  pv::synth::PitScan scan(spec);
  std::vector<pv_point_t> pts(n);
  for (auto &p : pts) p = scan.next();
  return pts;
}

struct Session {
  void *block = nullptr;
  pv_session_t *s = nullptr;
  size_t bytes = 0;
  explicit Session(pv_method_t method = PV_METHOD_SURFACE) {
    pv_config_t cfg;
    pv_config_default(&cfg);
    cfg.method = method;
    if (pv_session_size(&cfg, &bytes) != PV_OK) std::abort();
    const size_t rounded = (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
    block = std::aligned_alloc(PV_BLOCK_ALIGN, rounded);
    if (block == nullptr || pv_session_init(&cfg, block, bytes, &s) != PV_OK) {
      std::fprintf(stderr, "pitvol-bench: cannot set up a session of %zu bytes\n", bytes);
      std::exit(1);
    }
    // Touch the whole block once so that first-run page faults are not
    // charged to the first measurement.
    std::memset(block, 0, bytes);
    if (pv_session_init(&cfg, block, bytes, &s) != PV_OK) std::exit(1);
  }
  ~Session() { std::free(block); }
  Session(const Session &) = delete;
  Session &operator=(const Session &) = delete;
};

// A call the session refuses makes every figure after it meaningless.
void require(pv_status_t st, const char *what) {
  if (st == PV_OK) return;
  std::fprintf(stderr, "pitvol-bench: %s failed: %s (%s)\n", what, pv_status_message(st),
               pv_status_name(st));
  std::exit(1);
}

void push_all(pv_session_t *s, const std::vector<pv_point_t> &pts) {
  for (size_t i = 0; i < pts.size(); i += kBatch) {
    require(pv_session_push(s, pts.data() + i, std::min(kBatch, pts.size() - i)), "push");
  }
}

// Runs argv with stdout to out_path (default /dev/null) and stderr to
// /dev/null; returns the exit status or -1.
int run_quiet(const std::vector<std::string> &args, const char *out_path = "/dev/null") {
  std::vector<char *> argv;
  for (const auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct Row {
  std::string what, value, note;
};

std::string read_text(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The number after "key": in a flat JSON object, or NaN.
double json_number(const std::string &js, const std::string &key) {
  const size_t k = js.find("\"" + key + "\":");
  if (k == std::string::npos) return NAN;
  return std::strtod(js.c_str() + k + key.size() + 3, nullptr);
}

bool on_path(const char *prog) {
  const char *path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::string p(path);
  size_t b = 0;
  while (b <= p.size()) {
    size_t e = p.find(':', b);
    if (e == std::string::npos) e = p.size();
    const std::string f = p.substr(b, e - b) + "/" + prog;
    if (!p.substr(b, e - b).empty() && access(f.c_str(), X_OK) == 0) return true;
    b = e + 1;
  }
  return false;
}

// 4. Scaling: this program re-run as a child streams n points (seed 3) and
// finishes; it prints "n push_ms push_cpu_ms finish_ms finish_cpu_ms volume exact
// hwm_kib points_stored status".
int scale_child(uint64_t n) {
  pv::synth::PitSpec spec;
  spec.seed = 3;
  pv::synth::PitScan scan(spec);
  Session session;
  std::vector<pv_point_t> batch(kBatch);
  double push_ms = 0, push_cpu = 0;
  for (uint64_t done = 0; done < n;) {
    const size_t m = size_t(std::min<uint64_t>(kBatch, n - done));
    for (size_t i = 0; i < m; ++i) batch[i] = scan.next();
    const auto t0 = Clock::now();
    const double c0 = cpu_ms();
    require(pv_session_push(session.s, batch.data(), m), "push");
    push_cpu += cpu_ms() - c0;
    push_ms += ms_between(t0, Clock::now());
    done += m;
  }
  pv_result_t r{};
  const auto t0 = Clock::now();
  const double c0 = cpu_ms();
  const pv_status_t st = pv_session_finish(session.s, &r);
  const double finish_cpu = cpu_ms() - c0;
  const double finish_ms = ms_between(t0, Clock::now());
  std::printf("%llu %.3f %.3f %.3f %.3f %.6f %.6f %ld %llu %s\n", (unsigned long long)n, push_ms,
              push_cpu, finish_ms, finish_cpu, st == PV_OK ? r.volume_cm3 : NAN,
              pv::synth::exact_volume_cm3(spec), vm_hwm_kib(),
              (unsigned long long)r.points_stored, pv_status_name(st));
  return st == PV_OK ? 0 : 1;
}

std::string fmt(const char *f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string fmt_ms(double wall, double cpu) {
  return fmt("%.1f", wall) + " ms (CPU " + fmt("%.1f", cpu) + " ms)";
}

}  // namespace

int main(int argc, char **argv) {
  if (argc == 3 && std::strcmp(argv[1], "--scale-one") == 0) {
    return scale_child(uint64_t(std::atof(argv[2])));
  }
  bool markdown = false, no_peers = false;
  size_t ingest_points = 4000000, scan_points = 400000;
  std::vector<double> scale_sizes = {1e5, 1e6, 1e7};
  std::string cmdline;
  for (int i = 0; i < argc; ++i) cmdline += (i ? " " : "") + std::string(argv[i]);
  // The command line (CLI11, as pitvol's); errors one line, exit 2.
  CLI::App app{"Throughput and latency of the measuring core and the CLI (docs/benchmarks.md).",
               "pitvol-bench"};
  app.get_formatter()->label("Usage", "usage");
  const auto at_least_1000 = CLI::Range(size_t(1000), std::numeric_limits<size_t>::max()).description(">= 1000");
  app.add_flag("--markdown", markdown, "Markdown tables");
  app.add_option("--ingest-points", ingest_points, "points pushed for the ingest rate (default 4000000)")
      ->type_name("N")
      ->check(at_least_1000);
  app.add_option("--scan-points", scan_points, "points of the scan finished and replayed (default 400000)")
      ->type_name("N")
      ->check(at_least_1000);
  app.add_option("--scale", scale_sizes, "point counts of the scaling table (default 1e5,1e6,1e7)")
      ->delimiter(',')
      ->type_name("N,N,...")
      ->check(CLI::Range(1000.0, 1e12).description("each 1000 .. 1e12"));
  app.add_flag("--no-peers", no_peers, "no CloudCompare beside the CLI replay");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp &e) {
    return app.exit(e);
  } catch (const CLI::ParseError &e) {
    std::fprintf(stderr, "pitvol-bench: %s (pitvol-bench --help lists the options)\n", e.what());
    return 2;
  }
  const bool peers = !no_peers;
  std::vector<uint64_t> sizes;
  for (double n : scale_sizes) sizes.push_back(uint64_t(n));
  std::vector<Row> rows;

  // The child processes run first, while this process is still small: a
  // child started with posix_spawn/vfork inherits the parent's RSS
  // high-water mark at exec (Linux), so the CLI's ru_maxrss is only
  // meaningful before the benchmark holds its session block and points.
  // 3. whole-file replay through the CLI, and CloudCompare beside it
  const std::string pitvol = self_dir() + "/pitvol";
  const std::string self = self_dir() + "/pitvol-bench";
  std::string replay_value = "n/a", replay_note, cc_value, cc_note;
  const char *tmpenv = std::getenv("TMPDIR");
  std::string tmpl = std::string(tmpenv && *tmpenv ? tmpenv : "/tmp") + "/pitvol_bench_XXXXXX";
  std::vector<char> dir(tmpl.begin(), tmpl.end());
  dir.push_back('\0');
  pv::synth::PitSpec file_spec;
  file_spec.seed = 2;
  const double exact_cm3 = pv::synth::exact_volume_cm3(file_spec);
  const bool have_dir = mkdtemp(dir.data()) != nullptr;
  const std::string file = std::string(dir.data()) + "/replay.ply";
  const std::string json = std::string(dir.data()) + "/replay.json";
  const std::string levelled = std::string(dir.data()) + "/levelled.ply";
  double replay_med = NAN;
  if (access(pitvol.c_str(), X_OK) != 0) {
    replay_note = "skipped: " + pitvol + " not found";
  } else if (!have_dir) {
    replay_note = "skipped: cannot make a temp directory";
  } else if (!pv::synth::write_scan_ply(file.c_str(), file_spec, scan_points)) {
    replay_note = "skipped: cannot write " + file;
  } else {
    std::vector<double> replay_ms;
    int rc = 0;
    for (int r = 0; r < kReplayRuns && rc == 0; ++r) {
      const auto t0 = Clock::now();
      rc = run_quiet({pitvol, "measure", file, "--json", "--no-progress"}, json.c_str());
      const auto t1 = Clock::now();
      replay_ms.push_back(ms_between(t0, t1));
    }
    struct stat st{};
    stat(file.c_str(), &st);
    const double v = json_number(read_text(json), "volume_cm3");
    if (rc != 0) {
      replay_note = "failed: pitvol exited with " + std::to_string(rc);
    } else {
      replay_med = median(replay_ms);
      replay_value = fmt("%.1f", replay_med) + " ms";
      replay_note = "`pitvol measure FILE --json`, " + std::to_string(scan_points) +
                    "-point binary PLY (" + fmt("%.1f", double(st.st_size) / 1048576.0) +
                    " MiB), process start to exit, median of 3; volume " + fmt("%.1f", v) +
                    " cm3, error " + fmt("%+.3f", 100.0 * (v / exact_cm3 - 1.0)) + " %";
    }
  }
  rusage kids{};
  getrusage(RUSAGE_CHILDREN, &kids);
  if (!peers) {
    cc_note = "not run (--no-peers)";
  } else if (!on_path("CloudCompare")) {
    cc_note = "not installed (toolchain/install-deps.sh --peers)";
  } else if (std::isnan(replay_med)) {
    cc_note = "not run: no pitvol replay";
  } else {
    // Levelled by pitvol (untimed): CloudCompare's 2.5D volume needs a
    // levelled cloud and the rim height, as in docs/accuracy.md.
    run_quiet({pitvol, "measure", file, "--json", "--no-progress", "--export-levelled", levelled});
    double rim = -1;
    {
      std::ifstream in(levelled, std::ios::binary);
      std::string line;
      while (std::getline(in, line) && line != "end_header") {
        if (line.rfind("comment pitvol_rim_mm ", 0) == 0) rim = std::atof(line.c_str() + 22);
      }
    }
    if (!(rim > 0)) {
      cc_note = "not run: no levelled cloud from pitvol";
    } else {
      const std::string cmd = "cd '" + std::string(dir.data()) +
                              "' && QT_QPA_PLATFORM=offscreen exec CloudCompare -SILENT -NO_TIMESTAMP "
                              "-AUTO_SAVE OFF -O levelled.ply -VOLUME -GRID_STEP 2 -CONST_HEIGHT " +
                              fmt("%.6f", rim);
      std::vector<double> cc_ms;
      int rc = 0;
      for (int r = 0; r < kReplayRuns && rc == 0; ++r) {
        const auto t0 = Clock::now();
        rc = run_quiet({"/bin/sh", "-c", cmd});
        cc_ms.push_back(ms_between(t0, Clock::now()));
      }
      const std::string rep = read_text(std::string(dir.data()) + "/VolumeCalculationReport.txt");
      const size_t k = rep.find("Volume: ");
      std::string num;
      for (size_t i = k == std::string::npos ? rep.size() : k + 8; i < rep.size() && rep[i] != '\n'; ++i) {
        if (rep[i] != ',') num += rep[i];
      }
      const double v = num.empty() ? NAN : -std::strtod(num.c_str(), nullptr) / 1000.0;
      const double ccm = median(cc_ms);
      cc_value = fmt("%.1f", ccm) + " ms";
      cc_note = "CloudCompare 2.5D volume (`-VOLUME -GRID_STEP 2 -CONST_HEIGHT rim`, headless) on the "
                "same scan levelled by pitvol (levelling not timed), median of 3; volume " +
                fmt("%.1f", v) + " cm3, error " + fmt("%+.3f", 100.0 * (v / exact_cm3 - 1.0)) +
                " %; pitvol is " + fmt("%.1f", ccm / replay_med) + "x faster";
      std::remove((std::string(dir.data()) + "/VolumeCalculationReport.txt").c_str());
    }
  }
  std::remove(file.c_str());
  std::remove(json.c_str());
  std::remove(levelled.c_str());
  if (have_dir) rmdir(dir.data());

  // 4. scaling, one child per size
  struct ScaleRow {
    uint64_t n;
    double push_ms, push_cpu, finish_ms, finish_cpu, volume, exact;
    long hwm_kib;
    unsigned long long stored;
    std::string status;
  };
  std::vector<ScaleRow> scale;
  for (uint64_t n : sizes) {
    char out_path[] = "/tmp/pitvol_bench_scale_XXXXXX";
    const int fd = mkstemp(out_path);
    if (fd < 0) break;
    close(fd);
    const int rc = run_quiet({self, "--scale-one", std::to_string(n)}, out_path);
    ScaleRow r{n, NAN, NAN, NAN, NAN, NAN, NAN, -1, 0, rc == 0 ? "PV_OK" : "failed"};
    char status[64] = "";
    unsigned long long nn = 0;
    if (FILE *f = std::fopen(out_path, "r")) {
      if (std::fscanf(f, "%llu %lf %lf %lf %lf %lf %lf %ld %llu %63s", &nn, &r.push_ms, &r.push_cpu,
                      &r.finish_ms, &r.finish_cpu, &r.volume, &r.exact, &r.hwm_kib, &r.stored,
                      status) == 10) {
        r.status = status;
      }
      std::fclose(f);
    }
    std::remove(out_path);
    scale.push_back(r);
  }

  Session session;

  // 1. ingest rate
  const std::vector<pv_point_t> big = make_scan(ingest_points, 1);  // not timed
  std::vector<double> rates, cpu_rates;
  for (int r = 0; r < kIngestRuns; ++r) {
    require(pv_session_reset(session.s), "reset");
    const auto t0 = Clock::now();
    const double c0 = cpu_ms();
    push_all(session.s, big);
    const double c1 = cpu_ms();
    const auto t1 = Clock::now();
    rates.push_back(double(big.size()) / (ms_between(t0, t1) / 1000.0));
    cpu_rates.push_back(double(big.size()) / ((c1 - c0) / 1000.0));
  }
  const double ingest = median(rates);
  rows.push_back({"ingest (pv_session_push, batches of 4096)",
                  fmt("%.1f", ingest / 1e6) + " M points/s (CPU " + fmt("%.1f", median(cpu_rates) / 1e6) +
                      ")",
                  std::to_string(ingest_points) +
                      " points, whole stream (warm-up and refinements included), median of 5"});

  // 2. estimate and finish latency (the same scan as the replay file)
  const std::vector<pv_point_t> scan = make_scan(scan_points, 2);
  pv_result_t res{};
  {
    std::vector<double> est_ms, est_cpu;
    require(pv_session_reset(session.s), "reset");
    push_all(session.s, scan);
    for (int r = 0; r < kEstimateRuns; ++r) {
      const auto t0 = Clock::now();
      const double c0 = cpu_ms();
      const pv_status_t st = pv_session_estimate(session.s, &res);
      est_cpu.push_back(cpu_ms() - c0);
      est_ms.push_back(ms_between(t0, Clock::now()));
      if (st != PV_OK) {
        std::fprintf(stderr, "pitvol-bench: estimate failed: %s\n", pv_status_name(st));
        return 1;
      }
    }
    rows.push_back({"estimate() latency, surface (default)", fmt_ms(median(est_ms), median(est_cpu)),
                    std::to_string(scan_points) + "-point scan, after every push, median of " +
                        std::to_string(kEstimateRuns) + " (volume " + fmt("%.1f", res.volume_cm3) +
                        " cm3)"});
  }
  for (int m = 0; m < 2; ++m) {
    Session paper_session(PV_METHOD_PAPER);
    Session &ses = m == 0 ? session : paper_session;
    std::vector<double> finish_ms, finish_cpu;
    for (int r = 0; r < kFinishRuns; ++r) {
      require(pv_session_reset(ses.s), "reset");
      push_all(ses.s, scan);
      const auto t0 = Clock::now();
      const double c0 = cpu_ms();
      const pv_status_t st = pv_session_finish(ses.s, &res);
      finish_cpu.push_back(cpu_ms() - c0);
      const auto t1 = Clock::now();
      if (st != PV_OK) {
        std::fprintf(stderr, "pitvol-bench: finish failed: %s\n", pv_status_name(st));
        return 1;
      }
      finish_ms.push_back(ms_between(t0, t1));
    }
    rows.push_back({m == 0 ? "finish() latency, surface (default)" : "finish() latency, paper",
                    fmt_ms(median(finish_ms), median(finish_cpu)),
                    std::to_string(scan_points) + "-point scan, median of 5 (volume " +
                        fmt("%.1f", res.volume_cm3) + " cm3, error " +
                        fmt("%+.3f", 100.0 * (res.volume_cm3 / exact_cm3 - 1.0)) + " %)"});
  }

  rows.push_back({"whole-file replay (CLI)", replay_value, replay_note});
  rows.push_back({"CloudCompare 2.5D volume, same file", cc_value.empty() ? "n/a" : cc_value, cc_note});

  // 5. memory
  rows.push_back({"session block (pv_session_size, default config)",
                  std::to_string(session.bytes) + " B = " +
                      fmt("%.2f", double(session.bytes) / 1048576.0) + " MiB",
                  "fixed; does not grow with the scan"});
  rusage self_use{};
  getrusage(RUSAGE_SELF, &self_use);
  rows.push_back({"peak RSS, this benchmark", fmt("%.1f", double(self_use.ru_maxrss) / 1024.0) + " MiB",
                  "after all runs; includes the " +
                      fmt("%.1f", double(ingest_points * sizeof(pv_point_t)) / 1048576.0) +
                      " MiB of pre-generated points"});
  if (kids.ru_maxrss > 0) {
    rows.push_back({"peak RSS, pitvol CLI replay", fmt("%.1f", double(kids.ru_maxrss) / 1024.0) + " MiB",
                    "largest `pitvol measure` child"});
  }

  const std::string cpu = cpu_model();
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = -1;
  if (markdown) {
    std::printf("Machine: %s, %ld cores online, load average %.2f at the end; pitvol %s; command: `%s`\n\n",
                cpu.c_str(), cores, load[0], PV_VERSION_STRING, cmdline.c_str());
    std::printf("| measurement | result | conditions |\n|---|---|---|\n");
    for (const auto &r : rows) std::printf("| %s | %s | %s |\n", r.what.c_str(), r.value.c_str(), r.note.c_str());
    if (!scale.empty()) {
      std::printf("\nScaling (default method; a child process per size streams a synthetic pit, seed 3, "
                  "generated 4096 points at a time; exact volume %.1f cm3):\n\n",
                  scale[0].exact);
      std::printf("| points | push time | push rate (CPU) | points stored | finish() | peak RSS | volume | error | status |\n"
                  "|---|---|---|---|---|---|---|---|---|\n");
      for (const auto &r : scale) {
        std::printf("| %llu | %.0f ms (CPU %.0f) | %.1f M points/s (%.1f) | %llu | %.1f ms (CPU %.1f) | %.1f MiB | %.1f cm3 | %+.3f %% | %s |\n",
                    (unsigned long long)r.n, r.push_ms, r.push_cpu, double(r.n) / r.push_ms / 1e3,
                    double(r.n) / r.push_cpu / 1e3, r.stored, r.finish_ms, r.finish_cpu,
                    double(r.hwm_kib) / 1024.0, r.volume, 100.0 * (r.volume / r.exact - 1.0),
                    r.status.c_str());
      }
    }
  } else {
    std::printf("pitvol-bench (pitvol %s)\ncpu:     %s (%ld cores online, load %.2f)\ncommand: %s\n\n",
                PV_VERSION_STRING, cpu.c_str(), cores, load[0], cmdline.c_str());
    size_t w0 = 0, w1 = 0;
    for (const auto &r : rows) {
      w0 = std::max(w0, r.what.size());
      w1 = std::max(w1, r.value.size());
    }
    for (const auto &r : rows) {
      std::printf("%-*s  %-*s  %s\n", int(w0), r.what.c_str(), int(w1), r.value.c_str(), r.note.c_str());
    }
    if (!scale.empty()) {
      std::printf("\nscaling: points  push_ms  push_cpu_ms  stored  finish_ms  finish_cpu_ms  peak_rss_mib  volume_cm3  status\n");
    }
    for (const auto &r : scale) {
      std::printf("  %llu  %.0f  %.0f  %llu  %.1f  %.1f  %.1f  %.1f  %s\n", (unsigned long long)r.n,
                  r.push_ms, r.push_cpu, r.stored, r.finish_ms, r.finish_cpu,
                  double(r.hwm_kib) / 1024.0, r.volume, r.status.c_str());
    }
  }
  return 0;
}
