// pitvol-bench: throughput and latency of the measuring core and the CLI.
//
//   pitvol-bench [--markdown] [--ingest-points N] [--scan-points N]
//
// Measures, on one thread:
//   1. ingest rate of pv_session_push (points/s): N points of a synthetic
//      pit are generated into memory first (not timed), then only the push
//      calls, in batches of 4096, are timed; median of 5 runs, the session
//      is reset between runs;
//   2. pv_session_finish() latency (ms) for a scan of M points: median of 5;
//   3. whole-file replay: the M-point scan written as binary PLY (the
//      format of pitvol-synth) to a temp file, then `pitvol measure FILE
//      --json` run end to end (the pitvol binary next to this program);
//      median of 3;
//   4. memory: pv_session_size() for the default configuration, the peak
//      RSS of this process after the runs (it holds the N pre-generated
//      points) and the peak RSS of the pitvol CLI children.
// Times come from std::chrono::steady_clock.
#include <fcntl.h>
#include <limits.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "pitvol/pitvol.h"
#include "synth/synthetic_pit.h"

extern char **environ;

namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kBatch = 4096;
constexpr int kIngestRuns = 5;
constexpr int kFinishRuns = 5;
constexpr int kReplayRuns = 3;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
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
  Session() {
    pv_config_t cfg;
    pv_config_default(&cfg);
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

void push_all(pv_session_t *s, const std::vector<pv_point_t> &pts) {
  for (size_t i = 0; i < pts.size(); i += kBatch) {
    pv_session_push(s, pts.data() + i, std::min(kBatch, pts.size() - i));
  }
}

// Runs argv with stdout to /dev/null; returns the exit status or -1.
int run_quiet(const std::vector<std::string> &args) {
  std::vector<char *> argv;
  for (const auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
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

std::string fmt(const char *f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

const char kUsage[] =
    "usage: pitvol-bench [--markdown] [--ingest-points N] [--scan-points N]\n"
    "       pitvol-bench --help\n";

int usage() {
  std::fputs(kUsage, stderr);
  return 2;
}

}  // namespace

int main(int argc, char **argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  bool markdown = false;
  size_t ingest_points = 4000000, scan_points = 400000;
  std::string cmdline;
  for (int i = 0; i < argc; ++i) cmdline += (i ? " " : "") + std::string(argv[i]);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--markdown") {
      markdown = true;
    } else if ((a == "--ingest-points" || a == "--scan-points") && i + 1 < argc) {
      const long long v = std::atoll(argv[++i]);
      if (v < 1000) return usage();
      (a == "--ingest-points" ? ingest_points : scan_points) = size_t(v);
    } else {
      return usage();
    }
  }

  // The replay (3.) runs first, while this process is still small: a child started
  // with posix_spawn/vfork inherits the parent's RSS high-water mark at
  // exec (Linux), so the CLI's ru_maxrss is only meaningful before the
  // benchmark holds its session block and point arrays.
  // 3. whole-file replay through the CLI
  const std::string pitvol = self_dir() + "/pitvol";
  std::string replay_value = "n/a", replay_note;
  const char *tmpenv = std::getenv("TMPDIR");
  std::string tmpl = std::string(tmpenv && *tmpenv ? tmpenv : "/tmp") + "/pitvol_bench_XXXXXX";
  std::vector<char> dir(tmpl.begin(), tmpl.end());
  dir.push_back('\0');
  if (access(pitvol.c_str(), X_OK) != 0) {
    replay_note = "skipped: " + pitvol + " not found";
  } else if (mkdtemp(dir.data()) == nullptr) {
    replay_note = "skipped: cannot make a temp directory";
  } else {
    const std::string file = std::string(dir.data()) + "/replay.ply";
    pv::synth::PitSpec file_spec;
    file_spec.seed = 2;
    if (!pv::synth::write_scan_ply(file.c_str(), file_spec, scan_points)) {
      replay_note = "skipped: cannot write " + file;
    } else {
      std::vector<double> replay_ms;
      int rc = 0;
      for (int r = 0; r < kReplayRuns && rc == 0; ++r) {
        const auto t0 = Clock::now();
        rc = run_quiet({pitvol, "measure", file, "--json", "--no-progress"});
        const auto t1 = Clock::now();
        replay_ms.push_back(ms_between(t0, t1));
      }
      struct stat st{};
      stat(file.c_str(), &st);
      if (rc != 0) {
        replay_note = "failed: pitvol exited with " + std::to_string(rc);
      } else {
        replay_value = fmt("%.1f", median(replay_ms)) + " ms";
        replay_note = "`pitvol measure FILE --json`, " + std::to_string(scan_points) +
                      "-point binary PLY (" + fmt("%.1f", double(st.st_size) / 1048576.0) +
                      " MiB), process start to exit, median of 3";
      }
    }
    std::remove(file.c_str());
    rmdir(dir.data());
  }
  rusage kids{};
  getrusage(RUSAGE_CHILDREN, &kids);

  Session session;
  std::vector<Row> rows;

  // 1. ingest rate
  const std::vector<pv_point_t> big = make_scan(ingest_points, 1);  // not timed
  std::vector<double> rates;
  for (int r = 0; r < kIngestRuns; ++r) {
    pv_session_reset(session.s);
    const auto t0 = Clock::now();
    push_all(session.s, big);
    const auto t1 = Clock::now();
    rates.push_back(double(big.size()) / (ms_between(t0, t1) / 1000.0));
  }
  const double ingest = median(rates);
  rows.push_back({"ingest (pv_session_push, batches of 4096)", fmt("%.1f", ingest / 1e6) + " M points/s",
                  std::to_string(ingest_points) + " points, median of 5"});

  // 2. finish latency (the same scan as the replay file)
  const std::vector<pv_point_t> scan = make_scan(scan_points, 2);
  std::vector<double> finish_ms;
  pv_result_t res{};
  for (int r = 0; r < kFinishRuns; ++r) {
    pv_session_reset(session.s);
    push_all(session.s, scan);
    const auto t0 = Clock::now();
    const pv_status_t st = pv_session_finish(session.s, &res);
    const auto t1 = Clock::now();
    if (st != PV_OK) {
      std::fprintf(stderr, "pitvol-bench: finish failed: %s\n", pv_status_name(st));
      return 1;
    }
    finish_ms.push_back(ms_between(t0, t1));
  }
  rows.push_back({"finish() latency", fmt("%.1f", median(finish_ms)) + " ms",
                  std::to_string(scan_points) + "-point scan, median of 5 (volume " +
                      fmt("%.1f", res.volume_cm3) + " cm3)"});

  rows.push_back({"whole-file replay (CLI)", replay_value, replay_note});

  // 4. memory
  rows.push_back({"session block (pv_session_size, default config)",
                  std::to_string(session.bytes) + " B = " +
                      fmt("%.2f", double(session.bytes) / 1048576.0) + " MiB",
                  "fixed; does not grow with the scan"});
  rusage self{};
  getrusage(RUSAGE_SELF, &self);
  rows.push_back({"peak RSS, this benchmark", fmt("%.1f", double(self.ru_maxrss) / 1024.0) + " MiB",
                  "after all runs; includes the " +
                      fmt("%.1f", double(ingest_points * sizeof(pv_point_t)) / 1048576.0) +
                      " MiB of pre-generated points"});
  if (kids.ru_maxrss > 0) {
    rows.push_back({"peak RSS, pitvol CLI replay", fmt("%.1f", double(kids.ru_maxrss) / 1024.0) + " MiB",
                    "largest `pitvol measure` child"});
  }

  const std::string cpu = cpu_model();
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (markdown) {
    std::printf("Machine: %s, %ld cores online; pitvol %s; command: `%s`\n\n", cpu.c_str(), cores,
                PV_VERSION_STRING, cmdline.c_str());
    std::printf("| measurement | result | conditions |\n|---|---|---|\n");
    for (const auto &r : rows) std::printf("| %s | %s | %s |\n", r.what.c_str(), r.value.c_str(), r.note.c_str());
  } else {
    std::printf("pitvol-bench (pitvol %s)\ncpu:     %s (%ld cores online)\ncommand: %s\n\n",
                PV_VERSION_STRING, cpu.c_str(), cores, cmdline.c_str());
    size_t w0 = 0, w1 = 0;
    for (const auto &r : rows) {
      w0 = std::max(w0, r.what.size());
      w1 = std::max(w1, r.value.size());
    }
    for (const auto &r : rows) {
      std::printf("%-*s  %-*s  %s\n", int(w0), r.what.c_str(), int(w1), r.value.c_str(), r.note.c_str());
    }
  }
  return 0;
}
