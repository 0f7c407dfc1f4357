#include "peer_runner.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "grid25.h"

namespace pv::tools {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string quote(const std::string &s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string read_file(const std::string &path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string json_escape(const std::string &s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') {
      o += "\\n";
      continue;
    }
    o += c;
  }
  return o;
}

// The object that follows "peer": in a cache file, or "".
std::string json_object(const std::string &j, const std::string &key) {
  const size_t k = j.find("\"" + key + "\": {");
  if (k == std::string::npos) return "";
  const size_t a = j.find('{', k), b = j.find('}', a);
  return b == std::string::npos ? "" : j.substr(a, b - a + 1);
}

// The levelling and rim an exported cloud was made with: its header lines
// "comment pitvol_rim_mm ..." and "comment pitvol_transform ...".
std::string levelling_key(const std::string &ply) {
  std::ifstream in(ply, std::ios::binary);
  std::string line, key;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("comment pitvol_rim_mm", 0) == 0 || line.rfind("comment pitvol_transform", 0) == 0) {
      key += line.substr(15) + ";";
    }
  }
  return key;
}

// The same levelling: every number of the two keys equal within 1e-6 of its
// size (a micrometre on the 300 mm scale of a pit). A change in the order of
// a sum moves the plane by far less and changes no peer's volume; caching on
// the exact text would recompute minutes of Poisson for nothing.
bool same_levelling(const std::string &a, const std::string &b) {
  auto numbers = [](const std::string &k) {
    std::vector<double> v;
    std::stringstream ss(k);
    std::string w;
    while (ss >> w) {
      char *end = nullptr;
      const double x = std::strtod(w.c_str(), &end);
      if (end != w.c_str()) v.push_back(x);
    }
    return v;
  };
  const std::vector<double> x = numbers(a), y = numbers(b);
  if (x.empty() || x.size() != y.size()) return false;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!(std::fabs(x[i] - y[i]) <= 1e-6 * std::max(1.0, std::fabs(x[i])))) return false;
  }
  return true;
}

std::string entry(const PeerResult &r) {
  char b[256];
  std::snprintf(b, sizeof b, "{\"status\": \"%s\", \"volume_cm3\": %.6f, \"ms\": %.1f}",
                json_escape(r.status).c_str(), r.volume_cm3, r.ms);
  std::string s = b;
  const size_t k = s.find("\"volume_cm3\": nan");
  if (k != std::string::npos) s.replace(k, 17, "\"volume_cm3\": null");
  return s;
}

}  // namespace

std::string capture(const std::string &cmd, int *status) {
  std::string out;
  FILE *p = popen(cmd.c_str(), "r");
  if (!p) {
    *status = -1;
    return out;
  }
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  *status = pclose(p);
  return out;
}

std::string self_dir() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return ".";
  const std::string s(buf, size_t(n));
  return s.substr(0, s.find_last_of('/'));
}

Measured measure(const std::string &bin_dir, const std::string &file, const std::string &method,
                 const std::string &config) {
  int status = 0;
  const std::string out =
      capture(quote(bin_dir + "/pitvol") + " measure " + quote(file) + " --json --no-progress --method " +
                  method + (config.empty() ? "" : " --config " + quote(config)) + " 2>/dev/null",
              &status);
  Measured m;
  m.status = json_str(out, "status");
  if (m.status.empty()) m.status = "NO_OUTPUT";
  m.failed_check = json_str(out, "failed_check");
  m.message = json_str(out, "message");
  m.volume_cm3 = json_num(out, "volume_cm3");
  m.interval_cm3 = json_num(out, "interval_cm3");
  m.check_value = json_num(out, "check_value");
  m.points_in = json_num(out, "points_in");
  m.points_used = json_num(out, "points_used");
  m.total_ms = json_num(out, "total");
  return m;
}

std::string json_str(const std::string &j, const std::string &key) {
  const size_t k = j.find("\"" + key + "\": \"");
  if (k == std::string::npos) return "";
  const size_t a = k + key.size() + 5;
  std::string v;
  for (size_t i = a; i < j.size() && j[i] != '"'; ++i) {
    if (j[i] == '\\' && i + 1 < j.size()) ++i;
    v += j[i];
  }
  return v;
}

double json_num(const std::string &j, const std::string &key) {
  const size_t k = j.find("\"" + key + "\": ");
  if (k == std::string::npos) return NAN;
  const char *p = j.c_str() + k + key.size() + 4;
  if (std::string(p, 4) == "null") return NAN;
  return std::strtod(p, nullptr);
}

bool PeerRunner::known(const std::string &peer) {
  return peer == "grid25" || peer == "cloudcompare" || peer == "poisson";
}

std::map<std::string, PeerResult> PeerRunner::run(const std::string &case_name,
                                                  const std::string &scan,
                                                  const std::vector<std::string> &peers) {
  std::map<std::string, PeerResult> out;
  mkdir(opt_.cache_dir.c_str(), 0755);
  // One work folder per process: runs of different peers may share a cache.
  const std::string work = opt_.cache_dir + "/" + case_name + ".work" + std::to_string(getpid());
  mkdir(work.c_str(), 0755);
  const std::string ply = work + "/" + case_name + ".ply";
  int st = 0;
  const std::string js = capture(quote(opt_.bin_dir + "/pitvol") + " measure " + quote(scan) +
                                     " --json --no-progress --method " + opt_.export_method +
                                     " --export-levelled " + quote(ply) + " 2>/dev/null",
                                 &st);
  double rim = -1;
  std::ifstream probe(ply);
  const bool exported = probe.good();
  probe.close();
  // The rim only: the points are read by each peer.
  if (exported) {
    std::ifstream in(ply, std::ios::binary);
    std::string line;
    while (std::getline(in, line) && line != "end_header") {
      if (line.rfind("comment pitvol_rim_mm ", 0) == 0) rim = std::atof(line.c_str() + 22);
    }
  }
  if (!exported || !(rim > 0)) {
    const std::string why = "no levelled cloud from pitvol (" +
                            (json_str(js, "status").empty() ? "no output" : json_str(js, "status")) + ")";
    for (const std::string &p : peers) out[p] = PeerResult{why, NAN, NAN};
    std::remove(ply.c_str());
    rmdir(work.c_str());
    return out;
  }
  const std::string key = levelling_key(ply);
  const std::string cache_path = opt_.cache_dir + "/" + case_name + ".json";
  const std::string cache = read_file(cache_path);
  const bool cache_valid = same_levelling(json_str(cache, "levelling"), key);

  for (const std::string &p : peers) {
    // grid25 takes milliseconds: always computed (its cell may change).
    // CloudCompare's result holds for the grid step it was run with.
    std::string cached = cache_valid && p != "grid25" ? json_object(cache, p) : "";
    if (p == "cloudcompare" && json_num(cached, "grid_mm") != opt_.cc_grid_mm) cached.clear();
    if (!cached.empty()) {
      out[p] = PeerResult{json_str(cached, "status"), json_num(cached, "volume_cm3"),
                          json_num(cached, "ms")};
      continue;
    }
    if (p == "grid25") {
      out[p] = grid25(ply);
    } else if (opt_.cached_only) {
      out[p] = PeerResult{"not computed (--peers-cached-only)", NAN, NAN};
    } else if (p == "cloudcompare") {
      out[p] = cloudcompare(work, ply, rim);
    } else if (p == "poisson") {
      out[p] = poisson(ply);
    }
  }

  // Rewrite the cache with every peer known for this levelling (results of
  // peers not asked for this time are kept).
  std::map<std::string, std::string> entries;
  for (const char *p : {"grid25", "cloudcompare", "poisson"}) {
    const std::string e = cache_valid ? json_object(cache, p) : "";
    if (!e.empty()) entries[p] = e;
  }
  for (const auto &kv : out) {
    // Do not cache what says nothing about the scan (peer not installed,
    // not computed): it would hide the peer once it is there.
    const std::string &s = kv.second.status;
    if (s.rfind("not ", 0) == 0 || s.rfind("unavailable", 0) == 0) continue;
    entries[kv.first] = entry(kv.second);
    if (kv.first == "cloudcompare") {
      char g[48];
      std::snprintf(g, sizeof g, ", \"grid_mm\": %g}", opt_.cc_grid_mm);
      entries[kv.first].replace(entries[kv.first].size() - 1, 1, g);
    }
  }
  std::ofstream c(cache_path);
  c << "{\"case\": \"" << case_name << "\",\n \"levelling\": \"" << json_escape(key) << "\",\n"
    << " \"rim_mm\": " << rim;
  for (const auto &kv : entries) c << ",\n \"" << kv.first << "\": " << kv.second;
  c << "}\n";
  std::remove(ply.c_str());
  rmdir(work.c_str());
  return out;
}

PeerResult PeerRunner::grid25(const std::string &ply) {
  const auto t0 = Clock::now();
  std::vector<pv::peers::LevelledPoint> pts;
  double rim = 0;
  std::string err;
  if (!pv::peers::read_levelled_ply(ply, &pts, &rim, &err)) return PeerResult{err, NAN, NAN};
  pv::peers::Grid25Params p;
  p.cell_mm = opt_.grid_mm;
  const pv::peers::Grid25Result r = pv::peers::grid25_volume(pts, rim, p);
  const double ms = ms_since(t0);
  if (!r.ok) return PeerResult{r.error, NAN, ms};
  return PeerResult{"ok", r.volume_cm3, ms};
}

PeerResult PeerRunner::cloudcompare(const std::string &dir, const std::string &ply, double rim_mm) {
  int st = 0;
  capture("command -v CloudCompare >/dev/null 2>&1", &st);
  if (st != 0) return PeerResult{"not installed (toolchain/install-deps.sh --peers)", NAN, NAN};
  const std::string report = dir + "/VolumeCalculationReport.txt";
  std::remove(report.c_str());
  char h[64];
  std::snprintf(h, sizeof h, "%.6f", rim_mm);
  char g[32];
  std::snprintf(g, sizeof g, "%g", opt_.cc_grid_mm);
  const std::string name = ply.substr(ply.find_last_of('/') + 1);
  const auto t0 = Clock::now();
  capture("cd " + quote(dir) + " && QT_QPA_PLATFORM=offscreen CloudCompare -SILENT -NO_TIMESTAMP " +
              "-AUTO_SAVE OFF -O " + quote(name) + " -VOLUME -GRID_STEP " + g + " -CONST_HEIGHT " + h +
              " >/dev/null 2>&1",
          &st);
  const double ms = ms_since(t0);
  // "Volume: -9,616,413.100250": the loaded cloud is the ceiling, the
  // constant height the ground, so the pit (below the rim) is negative.
  const std::string text = read_file(report);
  std::remove(report.c_str());
  const size_t k = text.find("Volume: ");
  if (k == std::string::npos) return PeerResult{"CloudCompare wrote no volume report", NAN, ms};
  std::string num;
  for (size_t i = k + 8; i < text.size() && text[i] != '\n'; ++i) {
    if (text[i] != ',') num += text[i];
  }
  return PeerResult{"ok", -std::strtod(num.c_str(), nullptr) / 1000.0, ms};
}

std::string PeerRunner::python() {
  if (python_tried_) return python_;
  python_tried_ = true;
  const std::string setup = opt_.bin_dir + "/../peers/setup-venv.sh";
  const std::string venv = opt_.bin_dir + "/../peers-venv";
  int st = 0;
  std::string out = capture(quote(setup) + " " + quote(venv) + " 2>" + quote(venv + ".log"), &st);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  if (st != 0 || out.empty()) {
    python_error_ = "unavailable: Open3D did not install (see " + venv + ".log)";
    return "";
  }
  python_ = out;
  return python_;
}

PeerResult PeerRunner::poisson(const std::string &ply) {
  const std::string py = python();
  if (py.empty()) return PeerResult{python_error_, NAN, NAN};
  int st = 0;
  const std::string js =
      capture(quote(py) + " " + quote(opt_.bin_dir + "/../peers/poisson_volume.py") + " " + quote(ply) +
                  " 2>/dev/null",
              &st);
  const std::string status = json_str(js, "status");
  if (status.empty()) return PeerResult{"the Poisson script failed", NAN, NAN};
  if (status != "ok") return PeerResult{json_str(js, "message"), NAN, json_num(js, "ms")};
  return PeerResult{"ok", json_num(js, "volume_cm3"), json_num(js, "ms")};
}

}  // namespace pv::tools
