// pitvol-sim: simulated handheld scans of pits with exactly known volume.
//
//   pitvol-sim scan --family NAME [--no-ground] [--seed S] [--points N]
//                   [--noise MM] [--tilt MAX_DEG] --out PREFIX
//       writes PREFIX.ply, PREFIX.frames (USB frame stream), PREFIX.json
//   pitvol-sim corpus --out DIR
//       writes the standard corpus: DIR/<case>.ply, .frames, and
//       DIR/manifest.csv + DIR/manifest.json
//   pitvol-sim families
#include <sys/stat.h>

#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <string>
#include <vector>

#include "sim/corpus.h"
#include "sim/scan_writer.h"

namespace {

using namespace pv::sim;

const char kUsage[] =
    "usage: pitvol-sim scan --family NAME [--no-ground] [--seed S] [--points N]\n"
    "                       [--noise MM] [--tilt MAX_DEG] --out PREFIX\n"
    "       pitvol-sim corpus --out DIR\n"
    "       pitvol-sim families\n"
    "       pitvol-sim --help\n";

int usage(const char *why) {
  if (why) std::fprintf(stderr, "pitvol-sim: %s\n", why);
  std::fputs(kUsage, stderr);
  return 2;
}

std::string manifest_json(const CorpusCase &c, const Pit &pit, const WrittenScan &w,
                          const std::string &stem) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "{\"case\": \"%s\", \"family\": \"%s\", \"ground\": %s, \"seed\": %llu, "
                "\"scan_seed\": %llu, \"noise_mm\": %.3f, \"points\": %llu, \"usb_frames\": %llu, "
                "\"tilt_deg\": %.4f, \"exact_volume_cm3\": %.6f, \"ply\": \"%s.ply\", "
                "\"frames\": \"%s.frames\", \"params\": ",
                c.name.c_str(), family_name(c.family), c.ground ? "true" : "false",
                (unsigned long long)c.seed, (unsigned long long)c.scan.seed, c.scan.noise_mm,
                (unsigned long long)w.points, (unsigned long long)w.frames, w.tilt_deg,
                pit.volume_mm3 / 1000.0, stem.c_str(), stem.c_str());
  return buf + pit.params_json + "}";
}

bool run_case(const CorpusCase &c, const std::string &dir_or_prefix, bool prefix_given,
              std::string *json, std::string *csv_row) {
  const Pit pit = make_pit(c.family, c.ground, c.seed);
  const std::string stem = prefix_given ? dir_or_prefix : c.name;
  const std::string base = prefix_given ? dir_or_prefix : dir_or_prefix + "/" + c.name;
  WrittenScan w;
  std::string err;
  if (!write_scan(pit, c.scan, base + ".ply", base + ".frames", &w, &err)) {
    std::fprintf(stderr, "pitvol-sim: %s\n", err.c_str());
    return false;
  }
  const size_t slash = stem.find_last_of('/');
  *json = manifest_json(c, pit, w, slash == std::string::npos ? stem : stem.substr(slash + 1));
  char row[256];
  std::snprintf(row, sizeof row, "%s,%s,%d,%llu,%.3f,%llu,%.4f,%.6f", c.name.c_str(),
                family_name(c.family), int(c.ground), (unsigned long long)c.seed, c.scan.noise_mm,
                (unsigned long long)w.points, w.tilt_deg, pit.volume_mm3 / 1000.0);
  *csv_row = row;
  std::fprintf(stderr, "pitvol-sim: %-22s %8llu points  exact %.3f cm3\n", c.name.c_str(),
               (unsigned long long)w.points, pit.volume_mm3 / 1000.0);
  return true;
}

bool write_text(const std::string &path, const std::string &text) {
  FILE *f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  return std::fclose(f) == 0 && ok;
}

bool parse_num(const char *s, double *out) {
  char *end = nullptr;
  *out = std::strtod(s, &end);
  return end != s && *end == '\0';
}

}  // namespace

int main(int argc, char **argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  if (argc < 2) return usage(nullptr);
  const std::string cmd = argv[1];
  if (cmd == "families") {
    for (int f = 0; f < int(Family::kCount); ++f) std::printf("%s\n", family_name(Family(f)));
    return 0;
  }
  CorpusCase one;
  one.family = Family::Cylinder;
  one.ground = true;
  one.seed = 1;
  bool have_family = false;
  std::string out;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    double v = 0;
    if (a == "--out" && more) {
      out = argv[++i];
    } else if (a == "--family" && more) {
      if (!family_from_name(argv[++i], &one.family)) return usage("unknown --family (see: pitvol-sim families)");
      have_family = true;
    } else if (a == "--no-ground") {
      one.ground = false;
    } else if (a == "--seed" && more && parse_num(argv[i + 1], &v) && v >= 0) {
      one.seed = uint64_t(v);
      one.scan.seed = uint64_t(v);
      ++i;
    } else if (a == "--points" && more && parse_num(argv[i + 1], &v) && v >= 1000) {
      one.scan.target_points = uint32_t(v);
      ++i;
    } else if (a == "--noise" && more && parse_num(argv[i + 1], &v) && v >= 0 && v <= 5) {
      one.scan.noise_mm = v;
      ++i;
    } else if (a == "--tilt" && more && parse_num(argv[i + 1], &v) && v >= 0 && v <= 180) {
      one.scan.max_tilt_deg = v;
      ++i;
    } else {
      return usage(("unknown or incomplete option '" + a + "'").c_str());
    }
  }
  if (out.empty()) return usage("--out is required");
  std::string json, row;
  const std::string csv_head =
      "case,family,ground,seed,noise_mm,points,tilt_deg,exact_volume_cm3\n";
  if (cmd == "scan") {
    if (!have_family) return usage("scan needs --family");
    one.name = out;
    if (!run_case(one, out, true, &json, &row)) return 3;
    return write_text(out + ".json", json + "\n") ? 0 : 3;
  }
  if (cmd != "corpus") return usage("unknown command");
  mkdir(out.c_str(), 0755);
  std::string all_json = "[\n", all_csv = csv_head;
  const std::vector<CorpusCase> cases = standard_corpus();
  for (size_t i = 0; i < cases.size(); ++i) {
    if (!run_case(cases[i], out, false, &json, &row)) return 3;
    all_json += "  " + json + (i + 1 < cases.size() ? ",\n" : "\n");
    all_csv += row + "\n";
  }
  all_json += "]\n";
  if (!write_text(out + "/manifest.json", all_json) || !write_text(out + "/manifest.csv", all_csv)) {
    std::fprintf(stderr, "pitvol-sim: cannot write the manifest in %s\n", out.c_str());
    return 3;
  }
  return 0;
}
