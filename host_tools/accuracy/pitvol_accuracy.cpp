// pitvol-accuracy: replays a corpus made by `pitvol-sim corpus` through the
// product (`pitvol measure FILE --json`, the same binary a QA engineer runs)
// and reports how accurate it is, per family and overall.
//
//   pitvol-accuracy DIR [--markdown] [--method NAME ...]
//                       [--write-expected FILE] [--check FILE] [--every N]
//                       [--peers grid25,cloudcompare,poisson] [--peers-cache DIR]
//                       [--peers-cached-only] [--case NAME ...]
//                       [--peers-max-error PCT] [--grid-mm 1] [--cc-grid-mm 2]
//                       [--html OUT.html]
//   pitvol-accuracy SWEEP_DIR --envelope [--markdown] [--jobs N] [--peers ...]
//       the envelope table of a `pitvol-sim sweep` (envelope_table.h)
//
// --html writes the results per case and method to OUT-results.csv (the
// .html replaced) and makes OUT.html from it with build/report/
// accuracy_plots.py under /usr/bin/python3 (matplotlib; docs/report.md).
// --peers-max-error (the CTest label peers): fails unless every peer
// measured at least one case and each measured case is within PCT, a
// check that the peers run and read the clouds right, not a goal.
// --peers adds other programs' volumes of the same scans (peer_runner.h),
// and a table per family with pitvol's methods and the peers side by side;
// the peers measure the cloud levelled by the first --method. Their results
// are cached in --peers-cache (default DIR/peers/<case>.json).
// --case limits the run to the named cases (for computing slow peers in
// the background, case by case).
//
// --every N measures and checks every N-th case only (the sanitizer build).
// --write-expected records each case's result and its tolerance (a tracked
// CSV: any drift shows in the commit that caused it); --check fails every
// case whose |error| exceeds its recorded tolerance, or that no longer
// measures, and the interval when it holds the truth in under 95 % of 20 or
// more measured cases; it ends with "N passed, M failed".
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "envelope_table.h"
#include "peer_runner.h"

namespace {

using pv::tools::json_num;
using pv::tools::json_str;
using pv::tools::self_dir;

struct Case {
  std::string name, family;
  double exact_cm3 = 0;
};

struct Outcome {
  std::string status;  // PV_OK or the failure's name
  double volume_cm3 = NAN, error = NAN;  // error: relative
  double interval_cm3 = NAN, exact_cm3 = NAN;  // the method's +/- (methods that give one)
  double points_in = 0, points_used = 0, total_ms = 0;
};

std::vector<std::string> split(const std::string &line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, sep)) out.push_back(f);
  return out;
}

bool read_manifest(const std::string &dir, std::vector<Case> *cases) {
  std::ifstream in(dir + "/manifest.csv");
  if (!in) return false;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    const auto f = split(line, ',');
    if (f.size() < 8) return false;
    cases->push_back(Case{f[0], f[1], std::atof(f[7].c_str())});
  }
  return !cases->empty();
}

Outcome measure(const std::string &bin_dir, const std::string &file, const std::string &method,
                double exact_cm3) {
  const pv::tools::Measured m = pv::tools::measure(bin_dir, file, method);
  Outcome o;
  o.status = m.status;
  o.volume_cm3 = m.volume_cm3;
  o.points_in = m.points_in;
  o.points_used = m.points_used;
  o.total_ms = m.total_ms;
  o.interval_cm3 = m.interval_cm3;
  o.exact_cm3 = exact_cm3;
  if (o.status == "PV_OK") o.error = (o.volume_cm3 - exact_cm3) / exact_cm3;
  return o;
}

// A slow peer not computed yet (--peers-cached-only) is no refusal: such
// outcomes are left out of every figure.
bool computed(const Outcome &o) { return o.status.rfind("not computed", 0) != 0; }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Tolerance for the regression check, from the measured error: a quarter
// more than measured, at least 0.05 percentage points of headroom. A real
// regression moves errors by more; a change that improves a case passes.
double tolerance_pct(double error) {
  const double e = std::fabs(error) * 100.0;
  return e + std::max(0.05, 0.25 * e);
}

struct Stats {
  int n = 0, failed = 0;
  double sum_abs = 0, max_abs = 0, sum_in = 0, sum_used = 0, sum_ms = 0;
  int timed = 0;  // outcomes with a time
  int with_interval = 0, holds = 0;  // measured cases with an interval; those that hold the truth
  std::vector<double> half_width_pct;
  void add(const Outcome &o) {
    ++n;
    sum_in += o.points_in;
    if (std::isfinite(o.total_ms)) {
      sum_ms += o.total_ms;
      ++timed;
    }
    if (o.status != "PV_OK") {
      ++failed;
      return;
    }
    sum_used += o.points_used;
    if (o.interval_cm3 > 0) {
      ++with_interval;
      if (std::fabs(o.volume_cm3 - o.exact_cm3) <= o.interval_cm3) ++holds;
      half_width_pct.push_back(100 * o.interval_cm3 / o.volume_cm3);
    }
    sum_abs += std::fabs(o.error);
    max_abs = std::max(max_abs, std::fabs(o.error));
  }
  std::string row(const std::string &label, const std::string &method) const {
    char b[512];
    const int ok = n - failed;
    std::snprintf(b, sizeof b, "| %s | %s | %d | %d | %s | %s | %s | %.0f | %.0f | %.0f |", label.c_str(),
                  method.c_str(), n, failed,
                  ok ? fmt(100 * sum_abs / ok).c_str() : "-", ok ? fmt(100 * max_abs).c_str() : "-",
                  interval().c_str(), sum_in / n, ok ? sum_used / ok : 0.0, sum_ms / n);
    return b;
  }
  // "holds/measured, median +/-": how often the interval contains the truth
  // and its median half-width (the target: at least 95 % over the corpus).
  std::string interval() const {
    if (with_interval == 0) return "-";
    char b[64];
    std::snprintf(b, sizeof b, "%d/%d, +/-%.2f %%", holds, with_interval, median(half_width_pct));
    return b;
  }
  // A cell of the side-by-side table: "mean / max (measured/run)".
  std::string cell() const {
    const int ok = n - failed;
    char b[96];
    if (n == 0) return " - |";
    if (ok == 0) std::snprintf(b, sizeof b, " - (0/%d) |", n);
    else std::snprintf(b, sizeof b, " %.3f / %.3f (%d/%d) |", 100 * sum_abs / ok, 100 * max_abs, ok, n);
    return b;
  }
  // A row of a family's table: method, cases, refusals, errors, time.
  std::string short_row(const std::string &method) const {
    char b[512];
    const int ok = n - failed;
    std::snprintf(b, sizeof b, "| %s | %d | %d | %s | %s | %.0f |", method.c_str(), n, failed,
                  ok ? fmt(100 * sum_abs / ok).c_str() : "-", ok ? fmt(100 * max_abs).c_str() : "-",
                  timed ? sum_ms / timed : NAN);
    return b;
  }
  static std::string fmt(double pct) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3f %%", pct);
    return b;
  }
};

// --html: the results as CSV, then the plotting script on them.
int write_html(const std::string &out, const std::vector<Case> &cases,
               const std::vector<std::string> &methods, const std::vector<std::string> &peers,
               std::map<std::string, std::map<std::string, Outcome>> &results) {
  const size_t dot = out.rfind(".html");
  const std::string csv = (dot == std::string::npos ? out : out.substr(0, dot)) + "-results.csv";
  {
    std::ofstream f(csv);
    f << "case,family,method,peer,exact_cm3,volume_cm3,interval_cm3,error_pct,status\n";
    char b[512];
    std::vector<std::string> all = methods;
    all.insert(all.end(), peers.begin(), peers.end());
    for (const std::string &m : all) {
      const bool peer = std::find(peers.begin(), peers.end(), m) != peers.end();
      for (const Case &c : cases) {
        const Outcome &o = results[m][c.name];
        if (!computed(o)) continue;
        std::snprintf(b, sizeof b, "%s,%s,%s,%d,%.6f,%.6f,%.6f,%.6f,", c.name.c_str(),
                      c.family.c_str(), m.c_str(), peer ? 1 : 0, c.exact_cm3, o.volume_cm3,
                      o.interval_cm3, 100 * o.error);
        std::string status = o.status;
        std::replace(status.begin(), status.end(), ',', ';');
        f << b << status << "\n";
      }
    }
    if (!f) {
      std::fprintf(stderr, "pitvol-accuracy: cannot write %s\n", csv.c_str());
      return 3;
    }
  }
  const std::string script = self_dir() + "/../report/accuracy_plots.py";
  const std::string cmd = "/usr/bin/python3 '" + script + "' '" + csv + "' '" + out + "'";
  std::fflush(stdout);  // the tables before the script's line
  const int rc = std::system(cmd.c_str());
  if (rc != 0) {
    std::fprintf(stderr, "pitvol-accuracy: %s failed (exit %d): is python3-matplotlib installed "
                 "(toolchain/install-deps.sh)?\n", cmd.c_str(), rc);
    return 5;
  }
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  std::string dir;
  std::vector<std::string> methods;
  std::string write_expected, check, html_out;
  bool markdown = false, envelope = false;
  long every = 1;  // --every N: every N-th case only (the sanitizer build)
  std::vector<std::string> peers, only_cases;
  double peers_max_error = -1;
  pv::tools::PeerOptions popt;
  pv::tools::EnvelopeOptions eo;

  // The command line (CLI11, as pitvol's); errors one line, exit 2.
  CLI::App app{"Replays a corpus of simulated scans (pitvol-sim corpus) through pitvol measure and reports "
               "its accuracy per family and overall; with --envelope, the envelope table of a sweep "
               "(pitvol-sim sweep). docs/accuracy.md.",
               "pitvol-accuracy"};
  app.get_formatter()->label("Usage", "usage");
  app.add_option("DIR", dir, "the corpus, or with --envelope the sweep")->required();
  app.add_flag("--envelope", envelope, "the envelope table of a sweep");
  app.add_flag("--markdown", markdown, "Markdown tables");
  app.add_option("--method", methods, "surface (default), paper or polar; a corpus takes several")
      ->allow_extra_args(false)
      ->type_name("NAME");
  const auto peer_names = [](const std::string &p) {
    return pv::tools::PeerRunner::known(p) ? std::string()
                                           : "unknown peer '" + p + "' (known: grid25, cloudcompare, poisson)";
  };
  app.add_option("--peers", peers, "other programs' volumes of the same scans (docs/accuracy.md \"Peers\")")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->type_name("grid25,cloudcompare,poisson")
      ->check(peer_names, "");
  app.add_option("--peers-cache", popt.cache_dir, "the peers' results (default DIR/peers)")->type_name("DIR");
  app.add_flag("--peers-cached-only", popt.cached_only, "compute no peer result the cache lacks");
  // A corpus only (refused with --envelope).
  const std::string corpus_group = "A corpus only", sweep_group = "A sweep only (--envelope)";
  const std::vector<CLI::Option *> corpus_only = {
      app.add_option("--write-expected", write_expected, "record each case's result and tolerance")
          ->type_name("FILE"),
      app.add_option("--check", check, "fail every case outside its recorded tolerance")->type_name("FILE"),
      app.add_option("--every", every, "every N-th case only")->check(CLI::Range(1L, 1000000L)),
      app.add_option("--case", only_cases, "this case only (repeatable)")
          ->allow_extra_args(false)
          ->type_name("NAME"),
      app.add_option("--peers-max-error", peers_max_error,
                     "fail unless every peer measured a case and each within PCT")
          ->type_name("PCT"),
      app.add_option("--grid-mm", popt.grid_mm, "grid25's cell (default 1)")->check(CLI::PositiveNumber),
      app.add_option("--cc-grid-mm", popt.cc_grid_mm, "CloudCompare's grid step (default 2)")
          ->check(CLI::PositiveNumber),
      app.add_option("--html", html_out, "the results as a page (docs/report.md)")->type_name("OUT.html"),
  };
  for (CLI::Option *o : corpus_only) o->group(corpus_group);
  const std::vector<CLI::Option *> sweep_only = {
      app.add_option("--jobs", eo.jobs, "measure N scans at a time")->check(CLI::Range(1, 256)),
      app.add_option("--config", eo.config, "pitvol measure --config FILE")->type_name("FILE"),
      app.add_option("--title", eo.title, "a heading over the table"),
      app.add_option("--worst", eo.worst_n, "list the N worst scans (default 30)"),
  };
  for (CLI::Option *o : sweep_only) o->group(sweep_group);
  try {
    app.parse(argc, argv);
    for (CLI::Option *o : envelope ? corpus_only : sweep_only) {
      if (o->count() > 0)
        throw CLI::ValidationError(o->get_name(), envelope ? "not with --envelope (a corpus only)"
                                                           : "a sweep only: give --envelope");
    }
    if (envelope && methods.size() > 1) throw CLI::ValidationError("--method", "--envelope takes one method");
  } catch (const CLI::CallForHelp &e) {
    return app.exit(e);
  } catch (const CLI::ParseError &e) {
    std::fprintf(stderr, "pitvol-accuracy: %s (pitvol-accuracy --help lists the options)\n", e.what());
    return 2;
  }
  if (envelope) {
    eo.dir = dir;
    if (!methods.empty()) eo.method = methods[0];
    eo.markdown = markdown;
    eo.peers = peers;
    eo.popt = popt;
    return pv::tools::envelope_main(eo);
  }
  if (methods.empty()) methods.push_back("surface");  // the default method
  std::vector<Case> cases;
  if (!read_manifest(dir, &cases)) {
    std::fprintf(stderr, "pitvol-accuracy: no usable %s/manifest.csv (run pitvol-sim corpus --out %s)\n",
                 dir.c_str(), dir.c_str());
    return 3;
  }
  std::vector<std::string> skipped;  // left out by --every: not checked
  if (every > 1) {
    std::vector<Case> kept;
    for (size_t i = 0; i < cases.size(); ++i) {
      if (i % size_t(every) == 0) kept.push_back(cases[i]);
      else skipped.push_back(cases[i].name);
    }
    cases = kept;
  }
  if (!only_cases.empty()) {
    std::vector<Case> kept;
    for (const Case &c : cases) {
      if (std::find(only_cases.begin(), only_cases.end(), c.name) != only_cases.end()) kept.push_back(c);
    }
    if (kept.size() != only_cases.size()) {
      std::fprintf(stderr, "pitvol-accuracy: a --case is not in %s/manifest.csv\n", dir.c_str());
      return 2;
    }
    cases = kept;
  }
  const std::string bin_dir = pv::tools::self_dir();

  std::map<std::string, std::map<std::string, Outcome>> results;  // method -> case
  for (const std::string &m : methods) {
    for (const Case &c : cases) results[m][c.name] = measure(bin_dir, dir + "/" + c.name + ".ply", m, c.exact_cm3);
  }

  // The peers, on the cloud levelled by the first method.
  popt.bin_dir = self_dir();
  popt.export_method = methods[0];
  if (popt.cache_dir.empty()) popt.cache_dir = dir + "/peers";
  pv::tools::PeerRunner runner(popt);
  for (const Case &c : cases) {
    if (peers.empty()) break;
    const auto pr = runner.run(c.name, dir + "/" + c.name + ".ply", peers);
    for (const auto &kv : pr) {
      Outcome o;
      o.status = kv.second.status == "ok" ? "PV_OK" : kv.second.status;
      o.volume_cm3 = kv.second.volume_cm3;
      o.total_ms = kv.second.ms;
      if (o.status == "PV_OK") o.error = (o.volume_cm3 - c.exact_cm3) / c.exact_cm3;
      results[kv.first][c.name] = o;
    }
  }
  std::vector<std::string> all_methods = methods;
  all_methods.insert(all_methods.end(), peers.begin(), peers.end());

  // Per case, then per family and overall.
  std::printf("%s", markdown ? "| case | method | exact cm3 | measured cm3 | error | status |\n|---|---|---|---|---|---|\n" : "");
  for (const std::string &m : all_methods) {
    for (const Case &c : cases) {
      const Outcome &o = results[m][c.name];
      if (markdown) {
        std::printf("| %s | %s | %.2f | %.2f | %+.3f %% | %s |\n", c.name.c_str(), m.c_str(),
                    c.exact_cm3, o.volume_cm3, 100 * o.error, o.status.c_str());
      } else {
        std::printf("%-24s %-6s exact %10.2f  measured %10.2f  error %+8.3f %%  %s\n", c.name.c_str(),
                    m.c_str(), c.exact_cm3, o.volume_cm3, 100 * o.error, o.status.c_str());
      }
    }
  }
  std::printf("\n| family | method | cases | no measurement | mean abs error | max abs error | "
              "interval holds truth, median half-width | points in | points used | ms per case |\n"
              "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string &m : methods) {
    std::map<std::string, Stats> fam;
    std::vector<std::string> order;
    Stats all;
    for (const Case &c : cases) {
      if (!fam.count(c.family)) order.push_back(c.family);
      fam[c.family].add(results[m][c.name]);
      all.add(results[m][c.name]);
    }
    for (const std::string &f : order) std::printf("%s\n", fam[f].row(f, m).c_str());
    std::printf("%s\n", all.row("**all**", m).c_str());
  }

  if (!peers.empty()) {
    // One table per family: pitvol's methods and the peers side by side.
    std::vector<std::string> order;
    for (const Case &c : cases) {
      if (std::find(order.begin(), order.end(), c.family) == order.end()) order.push_back(c.family);
    }
    order.push_back("all");
    // A method's or peer's outcomes over a family ("all": every case).
    auto family_stats = [&](const std::string &m, const std::string &f) {
      Stats st;
      for (const Case &c : cases) {
        const Outcome &o = results[m][c.name];
        if (computed(o) && (f == "all" || c.family == f)) st.add(o);
      }
      return st;
    };
    for (const std::string &f : order) {
      std::printf("\n%s %s\n\n| method | cases | no measurement | mean abs error | max abs error | ms per case |\n"
                  "|---|---|---|---|---|---|\n",
                  markdown ? "####" : "family", f.c_str());
      for (const std::string &m : all_methods) {
        const Stats st = family_stats(m, f);
        if (st.n == 0) continue;
        const bool peer = std::find(peers.begin(), peers.end(), m) != peers.end();
        std::printf("%s\n", st.short_row(peer ? m + " (peer)" : m).c_str());
      }
    }
    // One table of all: a column per method and peer, "mean / max |error|
    // (cases measured of cases run)" per family, then the time per scan.
    std::printf("\n%s methods and peers side by side: mean / max |error| %% (measured / run)\n\n| family |",
                markdown ? "####" : "summary:");
    for (const std::string &m : all_methods) std::printf(" %s |", m.c_str());
    std::printf("\n|---|");
    for (size_t i = 0; i < all_methods.size(); ++i) std::printf("---|");
    std::printf("\n");
    for (const std::string &f : order) {
      std::printf("| %s |", f == "all" ? "**all**" : f.c_str());
      for (const std::string &m : all_methods) std::printf("%s", family_stats(m, f).cell().c_str());
      std::printf("\n");
    }
    // The same scans for every column: those no slow peer left out.
    std::vector<std::string> common;
    for (const Case &c : cases) {
      bool all_ran = true;
      for (const std::string &m : all_methods) all_ran &= computed(results[m][c.name]);
      if (all_ran) common.push_back(c.name);
    }
    if (common.size() < cases.size()) {
      std::printf("| **all, the %zu scans every column ran** |", common.size());
      for (const std::string &m : all_methods) {
        Stats st;
        for (const std::string &n : common) st.add(results[m][n]);
        std::printf("%s", st.cell().c_str());
      }
      std::printf("\n");
    }
    std::printf("| ms per scan, median |");
    for (const std::string &m : all_methods) {
      std::vector<double> t;
      for (const Case &c : cases) {
        const Outcome &o = results[m][c.name];
        if (computed(o) && std::isfinite(o.total_ms)) t.push_back(o.total_ms);
      }
      if (t.empty()) std::printf(" - |");
      else std::printf(" %.0f |", median(t));
    }
    std::printf("\n");
    // Why peers did not measure, once per reason.
    std::map<std::string, int> reasons;
    for (const std::string &p : peers) {
      for (const Case &c : cases) {
        const Outcome &o = results[p][c.name];
        if (o.status != "PV_OK" && computed(o)) ++reasons[p + ": " + o.status];
      }
    }
    if (!reasons.empty()) std::printf("\n");
    for (const auto &kv : reasons) std::printf("- %s (%d)\n", kv.first.c_str(), kv.second);
  }

  if (peers_max_error > 0) {
    int bad = 0;
    for (const std::string &p : peers) {
      int measured = 0;
      for (const Case &c : cases) {
        const Outcome &o = results[p][c.name];
        if (o.status != "PV_OK") continue;
        ++measured;
        if (std::fabs(100 * o.error) > peers_max_error) {
          std::printf("FAIL %s %s: error %+.3f %% beyond %.1f %%\n", p.c_str(), c.name.c_str(),
                      100 * o.error, peers_max_error);
          ++bad;
        }
      }
      if (measured == 0) {
        std::printf("FAIL %s measured no case\n", p.c_str());
        ++bad;
      }
    }
    std::printf("\npeers: %s\n", bad ? "FAILED" : "all measured cases within the bound");
    if (bad) return 1;
  }

  if (!html_out.empty()) {
    const int rc = write_html(html_out, cases, methods, peers, results);
    if (rc != 0) return rc;
  }

  const std::string &m0 = methods[0];
  if (!write_expected.empty()) {
    std::ofstream out(write_expected);
    out << "case,family,exact_volume_cm3,measured_volume_cm3,error_pct,tolerance_pct,status\n";
    char b[256];
    for (const Case &c : cases) {
      const Outcome &o = results[m0][c.name];
      std::snprintf(b, sizeof b, "%s,%s,%.6f,%.6f,%.4f,%.4f,%s\n", c.name.c_str(), c.family.c_str(),
                    c.exact_cm3, o.volume_cm3, 100 * o.error,
                    o.status == "PV_OK" ? tolerance_pct(o.error) : 0.0, o.status.c_str());
      out << b;
    }
    if (!out) {
      std::fprintf(stderr, "pitvol-accuracy: cannot write %s\n", write_expected.c_str());
      return 3;
    }
  }
  if (check.empty()) return 0;
  std::ifstream in(check);
  if (!in) {
    std::fprintf(stderr, "pitvol-accuracy: cannot read %s\n", check.c_str());
    return 3;
  }
  std::string line;
  std::getline(in, line);
  int passed = 0, failed = 0;
  while (std::getline(in, line)) {
    const auto f = split(line, ',');
    if (f.size() < 7) continue;
    const auto it = results[m0].find(f[0]);
    if (std::find(skipped.begin(), skipped.end(), f[0]) != skipped.end()) continue;
    if (it == results[m0].end()) {
      std::printf("FAIL %s: in %s but not in the corpus\n", f[0].c_str(), check.c_str());
      ++failed;
      continue;
    }
    const Outcome &o = it->second;
    const double tol = std::atof(f[5].c_str());
    bool ok;
    if (f[6] != "PV_OK") {
      ok = o.status != "PV_OK" || std::fabs(100 * o.error) <= 0.3;  // still refuses, or now measures well
    } else {
      ok = o.status == "PV_OK" && std::fabs(100 * o.error) <= tol;
    }
    if (!ok) {
      std::printf("FAIL %s: error %+.3f %% (%s), tolerance %.3f %%, recorded %s %s %%\n", f[0].c_str(),
                  100 * o.error, o.status.c_str(), tol, f[6].c_str(), f[4].c_str());
    }
    (ok ? passed : failed)++;
  }
  // The interval must hold the truth in at least 95 % of the measured cases
  // (a +/- that misses more often promises what it cannot); judged only over 20 cases or more (one miss in a handful
  // says nothing), so --every runs skip it.
  Stats all0;
  for (const Case &c : cases) all0.add(results[m0][c.name]);
  if (all0.with_interval >= 20) {
    const bool ok = all0.holds >= 0.95 * all0.with_interval;
    std::printf("%s interval: holds the truth in %s\n", ok ? "ok" : "FAIL", all0.interval().c_str());
    (ok ? passed : failed)++;
  }
  std::printf("\ncorpus: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
