#include "measure.h"

#include <unistd.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "export_levelled.h"
#include "export_report.h"
#include "out_file.h"
#include "pitvol/result_report.h"

namespace pv::tools {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Extent {
  double lo[3] = {INFINITY, INFINITY, INFINITY};
  double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  void add(const pv_point_t &p) {
    const double v[3] = {p.x_mm, p.y_mm, p.z_mm};
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(v[i])) return;
    }
    // Finite values: plain compares (std::fmin/fmax are library calls per
    // coordinate, a visible share of reading a large file).
    for (int i = 0; i < 3; ++i) {
      lo[i] = v[i] < lo[i] ? v[i] : lo[i];
      hi[i] = v[i] > hi[i] ? v[i] : hi[i];
    }
  }
  double largest_mm() const {
    double m = 0;
    for (int i = 0; i < 3; ++i) m = std::fmax(m, hi[i] - lo[i]);
    return m;
  }
};

// A soil test pit with its surroundings spans roughly 0.1 to 2 m.
std::string unit_warning(const Extent &e, const std::string &units) {
  const double span = e.largest_mm();
  if (!(span > 0)) return "";
  char buf[256];
  if (span < 5.0) {
    std::snprintf(buf, sizeof buf,
                  "the scan spans only %.3g mm with --units %s; it looks like metres: try --units m",
                  span, units.c_str());
  } else if (span < 50.0) {
    std::snprintf(buf, sizeof buf,
                  "the scan spans only %.3g mm with --units %s; it looks like centimetres: try --units cm",
                  span, units.c_str());
  } else if (span > 20000.0) {
    std::snprintf(buf, sizeof buf,
                  "the scan spans %.3g mm with --units %s, far more than a test pit; check the units",
                  span, units.c_str());
  } else {
    return "";
  }
  return buf;
}

class Progress {
 public:
  Progress(bool enabled, uint64_t total) : on_(enabled && total > (16u << 20) && isatty(2)), total_(total) {}
  void update(uint64_t done, uint64_t points) {
    if (!on_) return;
    const int pct = int(100.0 * double(done) / double(total_));
    if (pct == last_) return;
    last_ = pct;
    std::fprintf(stderr, "\rpitvol: reading %3d %%  %llu points", pct, (unsigned long long)points);
  }
  ~Progress() {
    if (on_ && last_ >= 0) std::fprintf(stderr, "\r%60s\r", "");
  }

 private:
  bool on_;
  uint64_t total_;
  int last_ = -1;
};

struct SessionBlock {
  void *ptr = nullptr;
  ~SessionBlock() { std::free(ptr); }
};

int input_error(const MeasureOptions &opt, const scanio::Error &e) {
  std::string where = opt.path;
  if (e.line > 0) where += ":" + std::to_string(e.line);
  else if (e.byte_offset > 0) where += ": byte " + std::to_string(e.byte_offset);
  if (opt.json) {
    const Json o = {{"status", "PV_ERR_INPUT"}, {"message", where + ": " + e.message}, {"volume_cm3", nullptr}};
    std::printf("%s\n", json_line(o).c_str());
  }
  std::fprintf(stderr, "pitvol: %s: %s\n", where.c_str(), e.message.c_str());
  return kExitInput;
}

}  // namespace

int run_measure(const MeasureOptions &opt) {
  const auto t_start = Clock::now();
  scanio::Error err;
  std::unique_ptr<scanio::ScanReader> reader = scanio::open_scan(opt.path, opt.format, &err);
  if (!reader) return input_error(opt, err);

  // Outputs are checked before the work: a bad path fails at once, not
  // after the measurement. Each is complete or absent (out_file.h).
  OutFile layers;
  std::string oerr;
  if (!opt.layers_csv.empty() && !layers.open(opt.layers_csv, &oerr)) {
    std::fprintf(stderr, "pitvol: --layers: %s\n", oerr.c_str());
    return kExitInput;
  }
  if (!opt.export_dir.empty() && !prepare_export_dir(opt.export_dir, &oerr)) {
    std::fprintf(stderr, "pitvol: --export: %s\n", oerr.c_str());
    return kExitInput;
  }

  size_t bytes = 0;
  if (pv_session_size(&opt.cfg, &bytes) != PV_OK) {
    std::fprintf(stderr, "pitvol: invalid configuration\n");
    return kExitUsage;
  }
  SessionBlock block;
  // The block in 2 MiB pages where the kernel offers them (transparent huge
  // pages on request): some 4,000 page faults of a 400k-point scan become
  // about 15 (with 4 KiB pages the faults are a tenth of the replay's CPU
  // time).
  constexpr size_t kHugePage = size_t(2) << 20;
  const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  block.ptr = std::aligned_alloc(kHugePage, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (block.ptr != nullptr) madvise(block.ptr, rounded, MADV_HUGEPAGE);
#endif
  pv_session_t *session = nullptr;
  if (block.ptr == nullptr || pv_session_init(&opt.cfg, block.ptr, bytes, &session) != PV_OK) {
    std::fprintf(stderr, "pitvol: cannot set up a session of %zu bytes\n", bytes);
    return kExitInternal;
  }

  // Fixed chunk: memory does not grow with the file.
  std::vector<pv_point_t> chunk(65536);
  Extent extent;
  uint64_t points = 0, exportable_points = 0;
  Progress progress(opt.progress, reader->bytes_total());
  for (;;) {
    const long n = reader->read(chunk.data(), chunk.size(), &err);
    if (n < 0) return input_error(opt, err);
    if (n == 0) break;
    // Millimetre files (the common case) need no scaling: a float times
    // 1.0 in double, back to float, is the same float.
    const bool scale = opt.scale_to_mm != 1.0;
    const bool count_exportable = !opt.export_levelled.empty() || !opt.export_dir.empty();
    for (long i = 0; i < n; ++i) {
      pv_point_t &p = chunk[size_t(i)];
      if (scale) {
        p.x_mm = float(p.x_mm * opt.scale_to_mm);
        p.y_mm = float(p.y_mm * opt.scale_to_mm);
        p.z_mm = float(p.z_mm * opt.scale_to_mm);
      }
      extent.add(p);
      if (count_exportable && exportable(p)) ++exportable_points;
    }
    points += uint64_t(n);
    // Bad points are counted, not refused: a push fails only on a session
    // that cannot take points, a bug of this program.
    const pv_status_t pst = pv_session_push(session, chunk.data(), size_t(n));
    if (pst != PV_OK) {
      std::fprintf(stderr, "pitvol: the session refused points: %s (%s)\n", pv_status_message(pst),
                   pv_status_name(pst));
      return kExitInternal;
    }
    progress.update(reader->bytes_consumed(), points);
  }
  const double read_ms = ms_since(t_start);
  if (points == 0) {
    err.message = "the file holds no points";
    return input_error(opt, err);
  }

  const auto t_finish = Clock::now();
  pv_result_t r{};
  const pv_status_t st = pv_session_finish(session, &r);
  const double finish_ms = ms_since(t_finish);
  // Output failures: one line each, exit 3 after the result is printed.
  std::vector<std::string> output_errors;
  if (layers) {
    write_layers_file(opt, session, layers.get());
    if (!layers.commit(&oerr)) output_errors.push_back("--layers: " + oerr);
  }
  if (!opt.export_levelled.empty() &&
      !export_levelled(opt, session, exportable_points, opt.export_levelled, &oerr)) {
    output_errors.push_back("--export-levelled: " + oerr);
  }
  const double total_ms = ms_since(t_start);

  std::vector<std::string> extra;
  const std::string uw = unit_warning(extent, opt.units);
  if (!uw.empty()) extra.push_back(uw);

  const bool ok = st == PV_OK;
  Json o = {{"pitvol_version", PV_VERSION_STRING},
            {"method", pv_method_name(opt.cfg.method)},
            {"file", opt.path},
            {"units", opt.units},
            {"status", pv_status_name(st)},
            {"message", pv_status_message(st)}};
  add_result_fields(&o, r, ok, extra);
  o["timings_ms"] = {{"read_and_push", read_ms}, {"finish", finish_ms}, {"total", total_ms}};
  // --export after the result: a refused scan is exported too (the report
  // shows why), and the files carry the same JSON as --json.
  if (!opt.export_dir.empty() && !export_report(opt, session, r, exportable_points, json_line(o), &oerr)) {
    output_errors.push_back("--export: " + oerr);
  }
  if (opt.json) {
    std::printf("%s\n", json_line(o).c_str());
  } else if (ok) {
    print_result_summary(stdout, r, opt.cfg.method, extra);
  } else {
    // A refusal says what to do; of the warnings only the tool's own (the
    // units) can explain it.
    for (const std::string &w : extra) std::fprintf(stderr, "pitvol: warning: %s\n", w.c_str());
  }
  if (!ok) print_refusal(stderr, "pitvol", st, r);
  for (const std::string &e : output_errors) {
    std::fprintf(stderr, "pitvol: %s%s\n", e.c_str(), ok ? " (the result above is valid)" : "");
  }
  if (!ok) return (st == PV_ERR_INTERNAL || st == PV_ERR_OUT_OF_MEMORY) ? kExitInternal : kExitNoMeasurement;
  if (!output_errors.empty()) return kExitInput;
  return kExitOk;
}

}  // namespace pv::tools
