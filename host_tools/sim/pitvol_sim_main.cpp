// pitvol-sim: simulated handheld scans of pits with exactly known volume.
//
//   pitvol-sim scan --family NAME [--no-ground] [--seed S] [--points N]
//                   [--noise MM] [--tilt MAX_DEG] [--arc DEG] [--dropouts N]
//                   [--ground-tilt DEG] [--depth MM] --out PREFIX
//       (--arc, --dropouts, --ground-tilt, --depth: the stress options of
//       ScanParams / PitOptions, see the stress corpus)
//       writes PREFIX.ply, PREFIX.frames (USB frame stream), PREFIX.json
//   pitvol-sim corpus [--set standard|holdout|stress] --out DIR
//       writes a corpus (default: the standard set): DIR/<case>.ply,
//       .frames, and DIR/manifest.csv + DIR/manifest.json (both name the set)
//   pitvol-sim slabs --family NAME [--no-ground] [--seed S] --layers FILE [--step MM]
//       the true void per height slab of that pit beside the measured one
//       (FILE: `pitvol measure SCAN --layers FILE`): where a measurement
//       loses or gains volume (docs/accuracy.md). Level ground only: the
//       pit's frame is then the levelled frame up to a turn about the axis.
//   pitvol-sim sweep --seed S [[--from I] --count N | --index I] [--family F]
//                    [--condition C] [--frames] [--thin F] --out DIR
//       the envelope sweep (sim/envelope.h; docs/accuracy.md, "The envelope
//       sweeps"): N random scans (cases I .. I+N-1 with --from; or case I
//       alone with --index) drawn from seed S, each
//       DIR/<case>.ply (and .frames with --frames), a 1x twin beside every
//       long, duplicated or slipped scan, DIR/manifest.csv + manifest.json.
//       --thin F: every scan's point count times F (quick sweeps in tests).
//       Seeds below 1000 are tuning seeds, 1000 and up fresh.
//   pitvol-sim sweep --seed S --index I [--family F] [--condition C]
//                    --slabs FILE [--step MM]
//       as slabs, for that sweep case's pit as drawn (its scale and shape;
//       a twin's pit is its case's): no scan is written.
//   pitvol-sim conditions
//   pitvol-sim families
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "sim/corpus.h"
#include "sim/envelope.h"
#include "sim/scan_writer.h"

namespace {

// The smallest volume pitvol measures (core: kMinVolumeCm3, README "What it
// measures"): under it a scan reads as one in other units.
constexpr double kBelowRangeMm3 = 600.0 * 1000.0;

using namespace pv::sim;

const char kUsage[] =
    "usage: pitvol-sim scan --family NAME [--no-ground] [--seed S] [--points N]\n"
    "                       [--noise MM] [--tilt MAX_DEG] [--arc DEG] [--dropouts N]\n"
    "                       [--ground-tilt DEG] [--depth MM] --out PREFIX\n"
    "       pitvol-sim corpus [--set standard|holdout|stress] --out DIR\n"
    "       pitvol-sim slabs --family NAME [--no-ground] [--seed S] --layers FILE [--step MM]\n"
    "       pitvol-sim sweep --seed S [[--from I] --count N | --index I] [--family F] [--condition C]\n"
    "                        [--frames] [--thin F] --out DIR\n"
    "       pitvol-sim sweep --seed S --index I [--family F] [--condition C] --slabs FILE [--step MM]\n"
    "       pitvol-sim conditions\n"
    "       pitvol-sim families\n"
    "       pitvol-sim --help\n";

int usage(const char *why) {
  if (why) std::fprintf(stderr, "pitvol-sim: %s\n", why);
  std::fputs(kUsage, stderr);
  return 2;
}

// The set, what the case stresses and the scan options that depart from a
// plain scan (dropout patches in the pit frame).
std::string set_json(const CorpusCase &c, const WrittenScan &w) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "\"set\": \"%s\", \"stress\": \"%s\", \"target_points\": %u, "
                "\"path_arc_deg\": %.3f, \"dropout_patches\": [",
                c.set.c_str(), c.stress.c_str(), unsigned(c.scan.target_points),
                c.scan.path_arc_deg);
  std::string s = buf;
  for (size_t i = 0; i < w.dropout_patches.size(); ++i) {
    const DropoutPatch &d = w.dropout_patches[i];
    std::snprintf(buf, sizeof buf,
                  "%s{\"x_mm\": %.3f, \"y_mm\": %.3f, \"z_mm\": %.3f, \"radius_mm\": %.3f}",
                  i ? ", " : "", d.x_mm, d.y_mm, d.z_mm, d.radius_mm);
    s += buf;
  }
  return s + "], ";
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
  std::string j = buf;
  // The set fields go in after the case's own (readers look fields up by name).
  const size_t at = j.find("\"ply\": ");
  return j.substr(0, at) + set_json(c, w) + j.substr(at) + pit.params_json + "}";
}

bool run_case(const CorpusCase &c, const std::string &dir_or_prefix, bool prefix_given,
              std::string *json, std::string *csv_row) {
  const Pit pit = make_pit(c.family, c.ground, c.seed, c.pit);
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
  std::snprintf(row, sizeof row, "%s,%s,%d,%llu,%.3f,%llu,%.4f,%.6f,%s,%s", c.name.c_str(),
                family_name(c.family), int(c.ground), (unsigned long long)c.seed, c.scan.noise_mm,
                (unsigned long long)w.points, w.tilt_deg, pit.volume_mm3 / 1000.0, c.set.c_str(),
                c.stress.c_str());
  *csv_row = row;
  std::fprintf(stderr, "pitvol-sim: %-32s %8llu points  exact %.3f cm3\n", c.name.c_str(),
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

// Layers of `pitvol measure --layers`: centre height and section, 0.5 mm
// steps (bottom first).
bool read_layers(const std::string &path, std::vector<double> *z, std::vector<double> *area) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line.rfind("z_mm,area_mm2", 0) != 0) return false;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string a, b;
    if (!std::getline(ss, a, ',') || !std::getline(ss, b, ',')) return false;
    z->push_back(std::atof(a.c_str()));
    area->push_back(std::atof(b.c_str()));
  }
  return z->size() >= 2;
}

// The pit's true void in slabs beside pitvol's section profile: a corpus
// pit (slabs), or a sweep draw's pit as drawn (sweep --slabs: its scale and
// shape, not the family's nominal pit).
int slabs_of(const Pit &pit, const std::string &layers_path, double step_mm) {
  std::vector<double> z, area;
  if (!read_layers(layers_path, &z, &area)) {
    std::fprintf(stderr, "pitvol-sim: %s is not a layers CSV of pitvol measure --layers\n",
                 layers_path.c_str());
    return 3;
  }
  const double h = z[1] - z[0];
  const auto per = size_t(std::max(1.0, std::round(step_mm / h)));
  std::printf("from_mm,to_mm,true_cm3,measured_cm3,diff_cm3,diff_radius_mm\n");
  double true_all = 0, meas_all = 0;
  for (size_t i = 0; i < z.size(); i += per) {
    const size_t j = std::min(z.size(), i + per);
    const double a = z[i] - 0.5 * h, b = z[j - 1] + 0.5 * h;
    double meas = 0;
    for (size_t k = i; k < j; ++k) meas += area[k] * h;
    const double truth = volume_below_mm3(pit.void_closed, b) - volume_below_mm3(pit.void_closed, a);
    // The difference as a shift of the wall: over the slab's side, the
    // circumference of the circle of the same section.
    const double side = 2.0 * std::sqrt(M_PI * std::max(truth, 0.0) / (b - a)) * (b - a);
    std::printf("%.2f,%.2f,%.3f,%.3f,%+.3f,%+.3f\n", a, b, truth / 1000, meas / 1000,
                (meas - truth) / 1000, side > 0 ? (meas - truth) / side : 0.0);
    true_all += truth;
    meas_all += meas;
  }
  std::printf("all,,%.3f,%.3f,%+.3f,\n", true_all / 1000, meas_all / 1000, (meas_all - true_all) / 1000);
  return 0;
}

int slabs(const CorpusCase &c, const std::string &layers_path, double step_mm) {
  return slabs_of(make_pit(c.family, c.ground, c.seed), layers_path, step_mm);
}

// One sweep case (and its twin): files in dir, manifest lines appended.
bool sweep_case(const EnvelopeCase &drawn, const std::string &dir, bool frames,
                std::string *json, std::string *csv) {
  std::vector<EnvelopeCase> todo = {drawn};
  if (!drawn.twin.empty()) todo.push_back(envelope_twin(drawn));
  const Pit pit = make_pit(drawn.family, drawn.ground, drawn.pit_seed, drawn.pit);
  for (EnvelopeCase c : todo) {
    const ScanPlan plan = envelope_plan(c, pit);
    WrittenPlan w;
    std::string err;
    const std::string base = dir + "/" + c.name;
    if (!write_scan_plan(pit, plan, base + ".ply", frames ? base + ".frames" : "", &w, &err)) {
      std::fprintf(stderr, "pitvol-sim: %s\n", err.c_str());
      return false;
    }
    // A scan that left over a tenth of the wall unseen may be refused for it.
    if (c.expect == "measure" && w.coverage.unseen_share > 0.1) c.expect = "gap_ok";
    // A scan that missed the rim (the wall's top and the ground at its edge)
    // in over half the round holds no rim to measure up to: pitvol asks for
    // it (NO_RIM). The operator's path looks into the pit; on the deepest
    // pits and sparse scans it leaves the wall's top out of view in most
    // sectors (seed 1315 #007, 784 mm deep: no point in the top 20 mm in 8
    // of 12 30 deg sectors, 26 of 36 rim sectors unseen).
    if ((c.expect == "measure" || c.expect == "gap_ok") &&
        2 * w.coverage.rim_unseen_sectors > w.coverage.rim_sectors)
      c.expect = "no_rim_ok";
    // A pit under the instrument's range (README: under 600 cm3 reads as a
    // scan in other units, PV_PIT_CHECK_TOO_SMALL) may be refused for it;
    // the draws reach 0.4 L (a rounded bowl 50 mm across the radius, 80 deep).
    if (c.expect == "measure" && pit.volume_mm3 < kBelowRangeMm3) c.expect = "below_range";
    *json += (json->empty() ? "  " : ",\n  ") + envelope_json(c, pit, w);
    *csv += envelope_csv_row(c, pit, w) + "\n";
    std::fprintf(stderr, "pitvol-sim: %-44s %9llu points  exact %12.3f cm3  unseen %.3f\n",
                 c.name.c_str(), (unsigned long long)w.scan.points, pit.volume_mm3 / 1000.0,
                 w.coverage.unseen_share);
  }
  return true;
}

int sweep(int argc, char **argv) {
  uint64_t seed = 0;
  long count = -1, index = -1, from = 0;
  bool have_seed = false, frames = false;
  double thin = 1.0;  // every point count times this (quick sweeps for tests)
  double step_mm = 10.0;
  SweepFilter filter;
  std::string out, layers;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    double v = 0;
    if (a == "--seed" && more && parse_num(argv[i + 1], &v) && v >= 1 && v < 1e15) {
      seed = uint64_t(v);
      have_seed = true;
      ++i;
    } else if (a == "--count" && more && parse_num(argv[i + 1], &v) && v >= 1 && v <= 100000) {
      count = long(v);
      ++i;
    } else if (a == "--index" && more && parse_num(argv[i + 1], &v) && v >= 0 && v < 100000) {
      index = long(v);
      ++i;
    } else if (a == "--from" && more && parse_num(argv[i + 1], &v) && v >= 0 && v < 100000) {
      from = long(v);
      ++i;
    } else if (a == "--family" && more) {
      filter.family = argv[++i];
    } else if (a == "--condition" && more) {
      filter.condition = argv[++i];
    } else if (a == "--frames") {
      frames = true;
    } else if (a == "--thin" && more && parse_num(argv[i + 1], &v) && v > 0 && v <= 1) {
      thin = v;
      ++i;
    } else if (a == "--out" && more) {
      out = argv[++i];
    } else if (a == "--slabs" && more) {
      layers = argv[++i];
    } else if (a == "--step" && more && parse_num(argv[i + 1], &v) && v >= 0.5 && v <= 1000) {
      step_mm = v;
      ++i;
    } else {
      return usage(("unknown or incomplete sweep option '" + a + "'").c_str());
    }
  }
  if (!layers.empty()) {
    if (!have_seed || index < 0) return usage("sweep --slabs needs --seed and --index");
    EnvelopeCase c;
    std::string err;
    if (!draw_envelope_case(seed, uint32_t(index), filter, &c, &err)) return usage(err.c_str());
    return slabs_of(make_pit(c.family, c.ground, c.pit_seed, c.pit), layers, step_mm);
  }
  if (!have_seed || out.empty() || (count < 0) == (index < 0))
    return usage("sweep needs --seed, --out and one of --count, --index");
  mkdir(out.c_str(), 0755);
  std::string json, csv;
  const long first = index >= 0 ? index : from, last = index >= 0 ? index + 1 : from + count;
  for (long i = first; i < last; ++i) {
    EnvelopeCase c;
    std::string err;
    if (!draw_envelope_case(seed, uint32_t(i), filter, &c, &err)) return usage(err.c_str());
    c.scan.target_points = uint32_t(std::max(1000.0, c.scan.target_points * thin));
    c.pass_points = uint32_t(c.pass_points * thin);
    if (!sweep_case(c, out, frames, &json, &csv)) return 3;
    // The manifest after every case: a sweep stopped part way is usable.
    if (!write_text(out + "/manifest.json", "[\n" + json + "\n]\n") ||
        !write_text(out + "/manifest.csv", envelope_csv_header() + "\n" + csv)) {
      std::fprintf(stderr, "pitvol-sim: cannot write the manifest in %s\n", out.c_str());
      return 3;
    }
  }
  return 0;
}

int run(int argc, char **argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  if (argc < 2) return usage(nullptr);
  const std::string cmd = argv[1];
  if (cmd == "sweep") return sweep(argc, argv);
  if (cmd == "conditions") {
    for (const std::string &c : envelope_conditions()) std::printf("%s\n", c.c_str());
    return 0;
  }
  if (cmd == "families") {
    for (int f = 0; f < int(Family::kCount); ++f) std::printf("%s\n", family_name(Family(f)));
    return 0;
  }
  CorpusCase one;
  one.family = Family::Cylinder;
  one.ground = true;
  one.seed = 1;
  one.set = "single";
  one.stress = "none";
  bool have_family = false;
  std::string out, set = "standard", layers;
  double step_mm = 10.0;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    double v = 0;
    if (a == "--out" && more) {
      out = argv[++i];
    } else if (a == "--layers" && more) {
      layers = argv[++i];
    } else if (a == "--step" && more && parse_num(argv[i + 1], &v) && v >= 0.5 && v <= 1000) {
      step_mm = v;
      ++i;
    } else if (a == "--set" && more) {
      set = argv[++i];
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
    } else if (a == "--arc" && more && parse_num(argv[i + 1], &v) && v > 0 && v <= 360) {
      one.scan.path_arc_deg = v;
      ++i;
    } else if (a == "--dropouts" && more && parse_num(argv[i + 1], &v) && v >= 0 && v <= 1000) {
      one.scan.dropout_patches = uint32_t(v);
      ++i;
    } else if (a == "--ground-tilt" && more && parse_num(argv[i + 1], &v) && v >= -15 && v <= 15) {
      one.pit.ground_tilt_deg = v;
      ++i;
    } else if (a == "--depth" && more && parse_num(argv[i + 1], &v) && v >= 20 && v <= 2000) {
      one.pit.depth_mm = v;
      ++i;
    } else {
      return usage(("unknown or incomplete option '" + a + "'").c_str());
    }
  }
  if (cmd == "slabs") {
    if (!have_family || layers.empty()) return usage("slabs needs --family and --layers");
    return slabs(one, layers, step_mm);
  }
  if (out.empty()) return usage("--out is required");
  std::string json, row;
  const std::string csv_head =
      "case,family,ground,seed,noise_mm,points,tilt_deg,exact_volume_cm3,set,stress\n";
  if (cmd == "scan") {
    if (!have_family) return usage("scan needs --family");
    one.name = out;
    if (!run_case(one, out, true, &json, &row)) return 3;
    return write_text(out + ".json", json + "\n") ? 0 : 3;
  }
  if (cmd != "corpus") return usage("unknown command");
  std::vector<CorpusCase> cases;
  if (!corpus_by_name(set, &cases)) return usage("unknown --set (standard, holdout or stress)");
  mkdir(out.c_str(), 0755);
  std::string all_json = "[\n", all_csv = csv_head;
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

int main(int argc, char **argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception &e) {  // bad pit options, Embree failures
    std::fprintf(stderr, "pitvol-sim: %s\n", e.what());
    return 3;
  }
}
