// The envelope table (envelope_table.h): every scan of a sweep through
// `pitvol measure FILE --json` (no --units, whatever the scan's unit: scans
// in cm and m test the unit guess), then per family, size class, surround
// and condition: scans, mean and max |error|, how often the interval holds
// the truth, refusals (false ones by the check that refused), and long,
// duplicated or slipped scans against their 1x twin; the targets
// met or missed over the whole sweep; the worst scans with the command that
// makes each again.
//
// What a scan should give is in its manifest (`expect`):
// - measure: a real pit scanned properly: any refusal is false;
// - gap_ok: the scan left over a tenth of the wall unseen: a WALL_GAP
//   refusal is right, any other false;
// - no_rim_ok: the scan missed the rim in over half the round: a NO_RIM
//   refusal is right, any other false;
// - refuse_or_hold (slips): refused, or the interval holds the truth;
// - refuse_or_right (cm and m scans measured as mm): refused, or right;
// - below_range: a pit under the 600 cm3 pitvol measures (README): refused
//   (TOO_SMALL), or right.
// The accuracy targets (mean, max, coverage, false refusals) are over
// measure, gap_ok and no_rim_ok scans, 1x twins included (each is a real pit scanned
// once); the tables by condition, family, size and surround hold the
// sweep's scans, with their twins as the comparison only.
#include "envelope_table.h"


#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "peer_runner.h"

namespace pv::tools {

namespace {

struct Scan {
  std::map<std::string, std::string> f;  // manifest columns
  std::string name, family, size, surround, condition, expect, twin, reproduce;
  double exact = NAN;
  bool is_twin = false;
};

// pitvol's result for a scan (NOT_RUN until measured).
struct Result : Measured {
  Result() { status = "NOT_RUN"; }
  Result(const Measured &m) : Measured(m) {}  // NOLINT: a Measured is a Result
  bool ok() const { return status == "PV_OK"; }
};

std::vector<std::string> split_csv(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

bool read_sweep(const std::string &dir, std::vector<Scan> *scans, std::string *error) {
  std::ifstream in(dir + "/manifest.csv");
  std::string line;
  if (!in || !std::getline(in, line)) {
    *error = "no " + dir + "/manifest.csv (pitvol-sim sweep --seed S --count N --out " + dir + ")";
    return false;
  }
  const std::vector<std::string> head = split_csv(line);
  if (std::find(head.begin(), head.end(), "condition") == head.end()) {
    *error = dir + "/manifest.csv is not a sweep's (no condition column): pitvol-sim sweep makes one";
    return false;
  }
  while (std::getline(in, line)) {
    const std::vector<std::string> v = split_csv(line);
    if (v.size() != head.size()) {
      *error = "malformed manifest line: " + line;
      return false;
    }
    Scan s;
    for (size_t i = 0; i < head.size(); ++i) s.f[head[i]] = v[i];
    s.name = s.f["case"];
    s.family = s.f["family"];
    s.size = s.f["size_class"];
    s.surround = s.f["surround"];
    s.condition = s.f["condition"];
    s.expect = s.f["expect"];
    s.twin = s.f["twin"];
    s.reproduce = s.f["reproduce"];
    s.exact = std::atof(s.f["exact_volume_cm3"].c_str());
    s.is_twin = s.f["set"] == "sweep-twin";
    scans->push_back(s);
  }
  return !scans->empty();
}

// Why a refusal happened, shortly: the failed check, else the status.
std::string reason(const Result &r) {
  std::string s = r.failed_check.empty() ? r.status : r.failed_check;
  for (const char *p : {"PV_PIT_CHECK_", "PV_ERR_"})
    if (s.rfind(p, 0) == 0) s = s.substr(std::strlen(p));
  return s;
}

double rel_error(const Scan &s, const Result &r) { return (r.volume_cm3 - s.exact) / s.exact; }

bool holds(const Scan &s, const Result &r) {
  return r.ok() && std::fabs(r.volume_cm3 - s.exact) <= r.interval_cm3;
}

// Whether a refusal is false, given what the scan should give.
bool false_refusal(const Scan &s, const Result &r) {
  if (r.ok()) return false;
  if (s.expect == "measure") return true;
  if (s.expect == "gap_ok") return reason(r) != "WALL_GAP";
  if (s.expect == "no_rim_ok") return reason(r) != "NO_RIM";
  return false;
}

// A result with PV_OK that a correct instrument would not give.
bool wrong_ok(const Scan &s, const Result &r) {
  return (s.expect == "refuse_or_hold" || s.expect == "refuse_or_right" ||
          s.expect == "below_range") && r.ok() && !holds(s, r);
}

bool accuracy_scan(const Scan &s) {
  return s.expect == "measure" || s.expect == "gap_ok" || s.expect == "no_rim_ok";
}

// Targets (the issue's, over every family, size and condition).
constexpr double kMeanTarget = 0.0005, kMaxTarget = 0.0025, kCoverageTarget = 0.95,
                 kFalseRefusalTarget = 0.002, kTwinTarget = 0.0005;

struct Cell {
  int scans = 0, measured = 0, with_interval = 0, holding = 0, refused = 0, false_refused = 0,
      wrong = 0, twins = 0, twins_within = 0, twin_refused = 0;
  double sum_abs = 0, max_abs = 0, max_twin = 0;
  std::map<std::string, int> false_by;
  void add(const Scan &s, const Result &r, const Result *twin) {
    ++scans;
    if (r.ok()) {
      ++measured;
      const double e = std::fabs(rel_error(s, r));
      sum_abs += e;
      max_abs = std::max(max_abs, e);
      if (r.interval_cm3 > 0) {
        ++with_interval;
        holding += holds(s, r);
      }
    } else {
      ++refused;
    }
    if (false_refusal(s, r)) {
      ++false_refused;
      ++false_by[reason(r)];
    }
    wrong += wrong_ok(s, r);
    if (twin && twin->ok()) {
      if (r.ok()) {
        ++twins;
        const double d = std::fabs(r.volume_cm3 - twin->volume_cm3) / s.exact;
        max_twin = std::max(max_twin, d);
        twins_within += d <= kTwinTarget;
      } else {
        ++twin_refused;
      }
    }
  }
};

std::string pct(double x, int digits = 3) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f %%", digits, 100 * x);
  return b;
}

std::string cell_refusals(const Cell &c) {
  std::string s = std::to_string(c.refused);
  if (c.false_refused == 0) return s;
  s += " (" + std::to_string(c.false_refused) + " false:";
  for (const auto &kv : c.false_by) s += " " + kv.first + " " + std::to_string(kv.second);
  return s + ")";
}

std::string row(const Cell &c) {
  char b[512];
  std::snprintf(b, sizeof b, " %d | %s | %s | %s | %s | %s | %s |", c.scans,
                c.measured ? pct(c.sum_abs / c.measured).c_str() : "-",
                c.measured ? pct(c.max_abs).c_str() : "-",
                c.with_interval ? (std::to_string(c.holding) + "/" + std::to_string(c.with_interval)).c_str()
                                : "-",
                cell_refusals(c).c_str(), c.wrong ? std::to_string(c.wrong).c_str() : "0",
                c.twins || c.twin_refused
                    ? (pct(c.max_twin) + " (" + std::to_string(c.twins_within) + "/" +
                       std::to_string(c.twins) + " within" +
                       (c.twin_refused ? ", " + std::to_string(c.twin_refused) + " refused" : "") + ")")
                          .c_str()
                    : "-");
  return b;
}

const char kHead[] =
    " scans | mean abs error | max abs error | interval holds | refused (false: by check) | "
    "wrong PV_OK | vs 1x twin: max (within 0.05 %) |";
const char kRule[] = "---|---|---|---|---|---|---|";

struct PeerCell {
  int run = 0, measured = 0;
  double sum = 0, max = 0;
};

std::string peer_text(const PeerCell &p) {
  if (p.run == 0) return "-";
  if (p.measured == 0) return "- (0/" + std::to_string(p.run) + ")";
  char b[96];
  std::snprintf(b, sizeof b, "%.3f / %.3f (%d/%d)", 100 * p.sum / p.measured, 100 * p.max, p.measured,
                p.run);
  return b;
}

}  // namespace

int envelope_main(const EnvelopeOptions &opt) {
  const std::string &dir = opt.dir, &method = opt.method, &title = opt.title, &config = opt.config;
  const bool markdown = opt.markdown;
  const int jobs = opt.jobs;
  const size_t worst_n = opt.worst_n;
  const std::vector<std::string> &peers = opt.peers;
  PeerOptions popt = opt.popt;
  std::vector<Scan> scans;
  std::string err;
  if (!read_sweep(dir, &scans, &err)) {
    std::fprintf(stderr, "pitvol-accuracy: %s\n", err.c_str());
    return 3;
  }

  // Measure, `jobs` at a time.
  const std::string bin_dir = self_dir();
  std::vector<Result> results(scans.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < scans.size(); i = next++)
      results[i] = Result(measure(bin_dir, dir + "/" + scans[i].name + ".ply", method, config));
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < jobs; ++j) pool.emplace_back(work);
  for (std::thread &t : pool) t.join();
  std::map<std::string, size_t> by_name;
  for (size_t i = 0; i < scans.size(); ++i) by_name[scans[i].name] = i;
  auto twin_of = [&](const Scan &s) -> const Result * {
    const auto it = by_name.find(s.twin);
    return s.twin.empty() || it == by_name.end() ? nullptr : &results[it->second];
  };

  // Peers, on the scans that are not twins (cached: DIR/peers).
  std::map<std::string, std::map<std::string, PeerResult>> peer_results;  // case -> peer
  if (!peers.empty()) {
    popt.bin_dir = bin_dir;
    popt.export_method = method;
    if (popt.cache_dir.empty()) popt.cache_dir = dir + "/peers";
    PeerRunner runner(popt);
    for (const Scan &s : scans)
      if (!s.is_twin) peer_results[s.name] = runner.run(s.name, dir + "/" + s.name + ".ply", peers);
  }

  // Per-scan results beside the manifest.
  {
    std::ofstream out(dir + "/envelope-" + method + ".csv");
    out << "case,family,size_class,surround,condition,expect,exact_cm3,status,failed_check,"
           "check_value,volume_cm3,interval_cm3,error_pct,holds,false_refusal,wrong_ok,twin_diff_pct\n";
    char b[512];
    for (size_t i = 0; i < scans.size(); ++i) {
      const Scan &s = scans[i];
      const Result &r = results[i];
      const Result *t = twin_of(s);
      const double td = t && t->ok() && r.ok() ? 100 * (r.volume_cm3 - t->volume_cm3) / s.exact : NAN;
      std::snprintf(b, sizeof b, "%s,%s,%s,%s,%s,%s,%.6f,%s,%s,%.6g,%.6f,%.6f,%.5f,%d,%d,%d,%.5f\n",
                    s.name.c_str(), s.family.c_str(), s.size.c_str(), s.surround.c_str(),
                    s.condition.c_str(), s.expect.c_str(), s.exact, r.status.c_str(), r.failed_check.c_str(),
                    r.check_value, r.volume_cm3, r.interval_cm3, r.ok() ? 100 * rel_error(s, r) : NAN,
                    int(holds(s, r)), int(false_refusal(s, r)), int(wrong_ok(s, r)), td);
      out << b;
    }
  }

  // The tables.
  const char *h4 = markdown ? "### " : "";
  size_t n_scans = 0, n_twins = 0;
  std::set<std::string> seeds;
  for (const Scan &s : scans) {
    (s.is_twin ? n_twins : n_scans)++;
    seeds.insert(s.f.at("sweep_seed"));
  }
  std::string seed_list;
  for (const std::string &s : seeds) seed_list += (seed_list.empty() ? "" : ", ") + s;
  if (!title.empty()) std::printf("%s%s\n\n", markdown ? "## " : "", title.c_str());
  std::printf("%zu scans (and %zu 1x twins) of sweep seed %s, method %s, `pitvol measure` "
              "without --units, %s.\n\n",
              n_scans, n_twins, seed_list.c_str(), method.c_str(),
              config.empty() ? "the default configuration" : ("--config " + config).c_str());

  // Targets.
  Cell all_acc, long_cell, dup_cell, slip_cell, unit_cell, refusal_cell;
  std::map<std::string, Cell> acc_by_family, acc_by_size;
  for (size_t i = 0; i < scans.size(); ++i) {
    const Scan &s = scans[i];
    const Result &r = results[i];
    // A 1x twin is a real pit scanned once, as a technician would: its
    // accuracy counts like any scan's (a wrong PV_OK on a twin is one).
    if (accuracy_scan(s)) {
      all_acc.add(s, r, nullptr);
      acc_by_family[s.family].add(s, r, nullptr);
      acc_by_size[s.size].add(s, r, nullptr);
    }
    if (s.is_twin) continue;
    const Result *t = twin_of(s);
    if (s.condition == "long") long_cell.add(s, r, t);
    if (s.condition == "duplicates") dup_cell.add(s, r, t);
    if (s.expect == "refuse_or_hold") slip_cell.add(s, r, t);
    if (s.expect == "refuse_or_right") unit_cell.add(s, r, nullptr);
  }
  auto met = [](bool ok) { return ok ? "met" : "**missed**"; };
  auto worst_cov = [](const std::map<std::string, Cell> &m) {
    std::string w = "-";
    double lo = 2;
    for (const auto &kv : m) {
      if (kv.second.with_interval == 0) continue;
      const double c = double(kv.second.holding) / kv.second.with_interval;
      if (c < lo) {
        lo = c;
        w = kv.first + " " + std::to_string(kv.second.holding) + "/" +
            std::to_string(kv.second.with_interval);
      }
    }
    return std::pair<double, std::string>(lo, w);
  };
  const auto wf = worst_cov(acc_by_family), ws = worst_cov(acc_by_size);
  std::printf("%sTargets\n\n| target | measured | |\n|---|---|---|\n", h4);
  const double mean = all_acc.measured ? all_acc.sum_abs / all_acc.measured : NAN;
  std::printf("| mean abs error <= 0.05 %% (%d measured real-pit scans, 1x twins included) | %s "
              "| %s |\n",
              all_acc.measured,
              pct(mean).c_str(), met(mean <= kMeanTarget));
  std::printf("| max abs error <= 0.25 %% | %s | %s |\n", pct(all_acc.max_abs).c_str(),
              met(all_acc.max_abs <= kMaxTarget));
  const double cov = all_acc.with_interval ? double(all_acc.holding) / all_acc.with_interval : NAN;
  std::printf("| interval holds the truth >= 95 %%, every family and size | %d/%d (%s); worst family "
              "%s, worst size %s | %s |\n",
              all_acc.holding, all_acc.with_interval, pct(cov, 1).c_str(), wf.second.c_str(),
              ws.second.c_str(), met(cov >= kCoverageTarget && wf.first >= kCoverageTarget &&
                                     ws.first >= kCoverageTarget));
  const double fr = all_acc.scans ? double(all_acc.false_refused) / all_acc.scans : NAN;
  std::string by;
  for (const auto &kv : all_acc.false_by) by += " " + kv.first + " " + std::to_string(kv.second) + ";";
  std::printf("| false refusals <= 0.2 %% of real-pit scans | %d/%d (%s):%s | %s |\n",
              all_acc.false_refused, all_acc.scans, pct(fr, 1).c_str(), by.c_str(),
              met(fr <= kFalseRefusalTarget));
  std::printf("| a longer scan within 0.05 %% of its 1x twin | %d/%d within, max %s; %d refused where "
              "the 1x measured | %s |\n",
              long_cell.twins_within, long_cell.twins, pct(long_cell.max_twin).c_str(),
              long_cell.twin_refused,
              met(long_cell.twins_within == long_cell.twins && long_cell.twin_refused == 0));
  std::printf("| exact duplicates neutral (within 0.05 %% of 1x) | %d/%d within, max %s; %d refused "
              "where the 1x measured | %s |\n",
              dup_cell.twins_within, dup_cell.twins, pct(dup_cell.max_twin).c_str(),
              dup_cell.twin_refused,
              met(dup_cell.twins_within == dup_cell.twins && dup_cell.twin_refused == 0));
  std::printf("| tracking slips refused or inside their interval | %d/%d (%d measured outside) | %s |\n",
              slip_cell.scans - slip_cell.wrong, slip_cell.scans, slip_cell.wrong,
              met(slip_cell.wrong == 0));
  std::printf("| cm and m scans (no --units) refused, never measured wrong | %d/%d (%d measured "
              "wrong) | %s |\n\n",
              unit_cell.scans - unit_cell.wrong, unit_cell.scans, unit_cell.wrong,
              met(unit_cell.wrong == 0));

  // Marginal tables, then the cross.
  auto table = [&](const char *what, const std::function<std::string(const Scan &)> &key) {
    std::map<std::string, Cell> cells;
    std::map<std::string, std::map<std::string, PeerCell>> pc;  // key -> peer
    Cell total;
    for (size_t i = 0; i < scans.size(); ++i) {
      const Scan &s = scans[i];
      if (s.is_twin) continue;
      cells[key(s)].add(s, results[i], twin_of(s));
      total.add(s, results[i], twin_of(s));
      for (const std::string &p : peers) {
        const auto it = peer_results.find(s.name);
        if (it == peer_results.end() || !it->second.count(p)) continue;
        const PeerResult &pr = it->second.at(p);
        if (pr.status.rfind("not computed", 0) == 0) continue;
        for (PeerCell *c : {&pc[key(s)][p], &pc["**all**"][p]}) {
          ++c->run;
          if (pr.status == "ok") {
            ++c->measured;
            const double e = std::fabs(pr.volume_cm3 - s.exact) / s.exact;
            c->sum += e;
            c->max = std::max(c->max, e);
          }
        }
      }
    }
    std::printf("%sBy %s\n\n| %s |%s", h4, what, what, kHead);
    for (const std::string &p : peers) std::printf(" %s mean / max (measured/run) |", p.c_str());
    std::printf("\n|---|%s", kRule);
    for (size_t i = 0; i < peers.size(); ++i) std::printf("---|");
    std::printf("\n");
    auto print = [&](const std::string &k, const Cell &c) {
      std::printf("| %s |%s", k.c_str(), row(c).c_str());
      for (const std::string &p : peers) std::printf(" %s |", peer_text(pc[k][p]).c_str());
      std::printf("\n");
    };
    for (const auto &kv : cells) print(kv.first, kv.second);
    print("**all**", total);
    std::printf("\n");
  };
  table("condition", [](const Scan &s) { return s.condition; });
  table("family", [](const Scan &s) { return s.family; });
  table("size class", [](const Scan &s) { return s.size; });
  table("surround", [](const Scan &s) { return s.surround; });

  std::map<std::string, Cell> cross;
  for (size_t i = 0; i < scans.size(); ++i) {
    const Scan &s = scans[i];
    if (!s.is_twin) cross[s.family + " | " + s.size + " | " + s.condition].add(s, results[i], twin_of(s));
  }
  std::printf("%sThe envelope: family x size x condition\n\n| family | size | condition |%s\n"
              "|---|---|---|%s\n",
              h4, kHead, kRule);
  for (const auto &kv : cross) std::printf("| %s |%s\n", kv.first.c_str(), row(kv.second).c_str());
  std::printf("\n");

  // The worst scans: false refusals, wrong PV_OK, intervals that missed
  // (by how many interval widths), longer scans off their twin.
  struct Finding {
    double badness;
    std::string text;
  };
  std::vector<Finding> worst;
  char b[1024];
  for (size_t i = 0; i < scans.size(); ++i) {
    const Scan &s = scans[i];
    const Result &r = results[i];
    const Result *t = s.is_twin ? nullptr : twin_of(s);
    std::string what;
    double bad = 0;
    if (false_refusal(s, r)) {
      std::snprintf(b, sizeof b, "false refusal: %s (%g)", reason(r).c_str(), r.check_value);
      what = b;
      bad = 100;
    } else if (wrong_ok(s, r)) {
      std::snprintf(b, sizeof b, "PV_OK, %+.3f %% +/- %.3f %%", 100 * rel_error(s, r), 100 * r.interval_cm3 / s.exact);
      what = b;
      bad = 50 + std::min(49.0, std::fabs(r.volume_cm3 - s.exact) / std::max(1e-9, r.interval_cm3));
    } else if (accuracy_scan(s) && r.ok() && !holds(s, r)) {
      std::snprintf(b, sizeof b, "outside its interval: %+.3f %% +/- %.3f %%", 100 * rel_error(s, r),
                    100 * r.interval_cm3 / s.exact);
      what = b;
      bad = std::min(49.0, std::fabs(r.volume_cm3 - s.exact) / std::max(1e-9, r.interval_cm3));
    }
    if (t && t->ok()) {
      if (!r.ok() && s.expect == "measure") {
        what += what.empty() ? "" : "; ";
        what += "the 1x twin measured";
      } else if (r.ok() && std::fabs(r.volume_cm3 - t->volume_cm3) / s.exact > kTwinTarget) {
        std::snprintf(b, sizeof b, "%s%+.3f %% from its 1x twin", what.empty() ? "" : "; ",
                      100 * (r.volume_cm3 - t->volume_cm3) / s.exact);
        what += b;
        bad = std::max(bad, 1.0 + 100 * std::fabs(r.volume_cm3 - t->volume_cm3) / s.exact);
      }
    }
    if (what.empty()) continue;
    std::snprintf(b, sizeof b, "| %s | %s | %.1f | %s | `%s` |", s.name.c_str(), s.expect.c_str(), s.exact,
                  what.c_str(), s.reproduce.c_str());
    worst.push_back({bad, b});
  }
  std::stable_sort(worst.begin(), worst.end(),
                   [](const Finding &a, const Finding &c) { return a.badness > c.badness; });
  std::printf("%sWorst scans (%zu of %zu with a finding)\n\n| scan | expect | exact cm3 | finding | "
              "makes it again |\n|---|---|---|---|---|\n",
              h4, std::min(worst_n, worst.size()), worst.size());
  for (size_t i = 0; i < worst.size() && i < worst_n; ++i) std::printf("%s\n", worst[i].text.c_str());
  std::printf("\nPer scan: %s/envelope-%s.csv\n", dir.c_str(), method.c_str());
  return 0;
}

}  // namespace pv::tools
