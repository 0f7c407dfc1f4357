// The envelope sweeps: see envelope.h. Every draw is from splitmix64, and
// the draws use +, -, *, / and sqrt only (log-uniform sizes by repeated
// square roots, Gaussians as sums of uniforms, directions by rejection), so
// a case is the same numbers on every x86-64.
#include "sim/envelope.h"
#include "pitvol/splitmix64.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pv::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Rng {
  uint64_t s;
  uint64_t next() { return pv_splitmix64_next(&s); }
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  int integer(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(next() % static_cast<uint64_t>(hi - lo + 1));
  }
  // About N(0, 1): the sum of four uniforms, centred and scaled.
  double gauss() {
    return (uniform() + uniform() + uniform() + uniform() - 2.0) * 1.7320508075688772;
  }
};

// The streams of case (seed, index): one per choice.
enum Stream : uint64_t {
  kCondition = 1,
  kFamily,
  kSurround,
  kSize,
  kScan,
  kDetails,
  kSeeds,
  kSurroundDetails,
  kJitter = 100,  // + pass
};

uint64_t stream_seed(uint64_t seed, uint32_t index, uint64_t stream) {
  Rng r{seed};
  r.s = r.next() ^ (static_cast<uint64_t>(index) * 0xD1B54A32D192ED03ull);
  r.s = r.next() ^ (stream * 0x8CB92BA72F3D8DD7ull);
  r.next();
  return r.next();
}

Rng stream(uint64_t seed, uint32_t index, uint64_t s) { return Rng{stream_seed(seed, index, s)}; }

// base^u for u in [0, 1], by the bits of u and repeated square roots.
double pow_unit(double base, double u) {
  double r = 1.0, f = base;
  for (int k = 0; k < 40; ++k) {
    f = std::sqrt(f);
    u *= 2.0;
    if (u >= 1.0) {
      r *= f;
      u -= 1.0;
    }
  }
  return r;
}

double log_uniform(Rng &r, double lo, double hi) { return lo * pow_unit(hi / lo, r.uniform()); }

// Millimetres quantised to 1/1024 mm (as the families' draws are).
double q(double x) { return std::round(x * 1024.0) / 1024.0; }

// A family's nominal size as drawn (radius, depth), the smallest radius
// its floor can have at that size (0: no flat floor), and its deepest draw
// where that is far from the nominal (0: within 4 % of it).
struct Nominal {
  double radius, depth, floor_radius, deepest = 0.0;
};

Nominal nominal(Family f) {
  switch (f) {
    case Family::Textured: return {110, 290, 95};
    case Family::Tapered: return {110, 290, 80};
    case Family::Bowl: return {110, 290, 0};
    case Family::Necking: return {110, 290, 104};
    case Family::Elliptical: return {110, 290, 80};
    case Family::HandDug: return {110, 280, 90};
    case Family::ShallowWide: return {200, 100, 195};
    case Family::DeepNarrow: return {75, 400, 72};
    case Family::RoundedBowl: return {110, 200, 0, 250};
    default: return {110, 290, 105};  // cylinder, protrusions, bulge
  }
}

struct Weighted {
  const char *name;
  double weight;
};

// The conditions and how often each is drawn.
const Weighted kConditions[] = {
    {"nominal", 3.0},       {"long", 2.0},      {"duplicates", 1.0}, {"slip_vertical", 1.0},
    {"slip_lateral", 1.0},  {"units_cm", 0.5},  {"units_m", 0.5},    {"stones", 1.0},
    {"grooves", 1.0},       {"tilted", 1.0},    {"arc", 1.0},        {"ground_tilt", 0.5},
    {"sparse", 0.5},
};

bool needs_floor(const std::string &condition) { return condition == "stones"; }

std::string fmt(const char *f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

uint64_t pass_seed(uint64_t scan_seed, uint32_t pass) {
  Rng r{scan_seed ^ (static_cast<uint64_t>(pass) * 0xA0761D6478BD642Full)};
  r.next();
  return r.next() | 1u;  // never 0 (0 means "the scan's own seed")
}

}  // namespace

const std::vector<std::string> &envelope_conditions() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Weighted &w : kConditions) v.push_back(w.name);
    return v;
  }();
  return names;
}

const char *size_class(double volume_cm3) {
  if (volume_cm3 < 3000.0) return "<3 L";
  if (volume_cm3 < 30000.0) return "3-30 L";
  if (volume_cm3 < 150000.0) return "30-150 L";
  return ">150 L";
}

bool draw_envelope_case(uint64_t seed, uint32_t index, const SweepFilter &filter,
                        EnvelopeCase *out, std::string *error) {
  EnvelopeCase c;
  c.sweep_seed = seed;
  c.index = index;

  // Condition.
  {
    Rng r = stream(seed, index, kCondition);
    double total = 0.0;
    for (const Weighted &w : kConditions) total += w.weight;
    double u = r.uniform(0.0, total);
    c.condition = kConditions[0].name;
    for (const Weighted &w : kConditions) {
      if (u < w.weight) {
        c.condition = w.name;
        break;
      }
      u -= w.weight;
    }
    if (!filter.condition.empty()) {
      const auto &all = envelope_conditions();
      if (std::find(all.begin(), all.end(), filter.condition) == all.end()) {
        *error = "unknown condition '" + filter.condition + "'";
        return false;
      }
      c.condition = filter.condition;
    }
  }
  // Family: among those with a flat floor when the condition needs one.
  {
    Rng r = stream(seed, index, kFamily);
    std::vector<Family> fams;
    for (int f = 0; f < static_cast<int>(Family::kCount); ++f) {
      if (needs_floor(c.condition) && nominal(Family(f)).floor_radius == 0) continue;
      fams.push_back(Family(f));
    }
    c.family = fams[static_cast<size_t>(r.integer(0, static_cast<int>(fams.size()) - 1))];
    if (!filter.family.empty()) {
      if (!family_from_name(filter.family, &c.family)) {
        *error = "unknown family '" + filter.family + "'";
        return false;
      }
      if (needs_floor(c.condition) && nominal(c.family).floor_radius == 0) {
        if (!filter.condition.empty()) {
          *error = "condition '" + c.condition + "' needs a family with a flat floor";
          return false;
        }
        c.condition = "nominal";  // a floorless family forced on a stones draw
      }
    }
  }
  // Surround.
  {
    Rng r = stream(seed, index, kSurround);
    const double u = r.uniform();
    c.surround = u < 0.5 ? "ground" : (u < 0.75 ? "none" : "container");
    if (c.condition == "ground_tilt") c.surround = "ground";
    c.ground = c.surround == "ground";
  }
  // Pit and scan seeds.
  {
    Rng r = stream(seed, index, kSeeds);
    c.pit_seed = r.next() >> 16;
    c.scan.seed = (r.next() >> 16) | 1u;
  }
  // Size: the size class first (each a quarter of the cases), the volume
  // log-uniform in it, the depth-to-diameter ratio about the family's own;
  // then the radius of a cylinder of that volume and ratio, within 50-750
  // mm, and its depth within 80-800 mm.
  const Nominal nom = nominal(c.family);
  {
    Rng r = stream(seed, index, kSize);
    const double lo[] = {800.0, 3000.0, 30000.0, 150000.0}, hi[] = {3000.0, 30000.0, 150000.0, 600000.0};
    const int k = r.integer(0, 3);
    const double v_mm3 = 1000.0 * log_uniform(r, lo[k], hi[k]);
    const double ratio = std::min(3.0, nom.depth / (2.0 * nom.radius) * log_uniform(r, 0.35, 1.4));
    // V = pi R^2 (2 R ratio): R = cbrt(V / (2 pi ratio)), by Newton's steps.
    const double a = v_mm3 / (2.0 * kPi * ratio);
    double R = 200.0;
    for (int i = 0; i < 100; ++i) R = (2.0 * R + a / (R * R)) / 3.0;
    R = std::clamp(R, 50.0, 750.0);
    // The deepest draw of a family stays within 800 mm (rounded bowls are
    // drawn 150-250 mm deep about their 200: scaled to 800 one reached
    // 986 mm, past the 960 mm pitvol measures, fresh seed 1311 #234).
    const double deepest = nom.deepest > 0.0 ? 800.0 * nom.depth / nom.deepest : 800.0;
    const double depth = std::clamp(v_mm3 / (kPi * R * R), 80.0, deepest);
    c.target_radius_mm = R;
    c.target_depth_mm = depth;
    c.pit.scale_xy = R / nom.radius;
    c.pit.scale_z = depth / nom.depth;
  }
  const double R = c.target_radius_mm, depth = c.target_depth_mm;
  // Surround details.
  {
    Rng r = stream(seed, index, kSurroundDetails);
    const double ring = r.uniform(40.0, 80.0) * std::max(1.0, R / 150.0);
    const double lip = r.uniform(3.0, 15.0);
    if (c.surround == "ground") c.pit.ground_width_mm = q(ring);
    if (c.surround == "container") {
      c.pit.container_lip_mm = q(lip);
      c.scan.outside_views = 0.15;  // part of the outer wall in the scan
    }
  }
  // Scan.
  uint32_t base = 0;
  {
    Rng r = stream(seed, index, kScan);
    c.scan.noise_mm = log_uniform(r, 0.02, 0.2);
    c.scan.max_tilt_deg = 25.0;
    const double area = 2.0 * kPi * R * depth + kPi * R * R;
    const double area0 = 2.0 * kPi * 110.0 * 290.0 + kPi * 110.0 * 110.0;
    const double pts = 300000.0 * std::sqrt(area / area0) * r.uniform(0.8, 1.25);
    base = static_cast<uint32_t>(std::clamp(pts, 80000.0, 1000000.0));
    c.scan.target_points = base;
  }
  // The condition's own draws.
  {
    Rng r = stream(seed, index, kDetails);
    const std::string &k = c.condition;
    if (k == "long") {
      c.passes = static_cast<uint32_t>(r.integer(2, 30));
      const double cap = std::min(10.0 * base, 3.0e6);
      c.pass_points = static_cast<uint32_t>(std::min<double>(base, cap / c.passes));
      c.jitter_mm = 0.05;
    } else if (k == "duplicates") {
      c.copies = static_cast<uint32_t>(r.integer(2, 5));
      c.interleave = r.uniform() < 0.5;
    } else if (k == "slip_vertical" || k == "slip_lateral") {
      const double m = r.uniform(2.0, 30.0);
      c.passes = 2;
      c.pass_points = static_cast<uint32_t>(base * r.uniform(0.3, 1.0));
      if (k == "slip_vertical") {
        c.slip_mm[2] = r.uniform() < 0.5 ? -m : m;
      } else {
        double x = 0, y = 0, n2 = 0;
        do {
          x = r.uniform(-1.0, 1.0);
          y = r.uniform(-1.0, 1.0);
          n2 = x * x + y * y;
        } while (n2 > 1.0 || n2 < 0.01);
        const double n = std::sqrt(n2);
        c.slip_mm[0] = m * x / n;
        c.slip_mm[1] = m * y / n;
      }
      c.expect = "refuse_or_hold";
    } else if (k == "units_cm" || k == "units_m") {
      c.units = k == "units_cm" ? "cm" : "m";
      c.expect = "refuse_or_right";
    } else if (k == "stones") {
      // One stone and 0-6 loose lumps, inside the smallest floor radius.
      const double floor_r = nom.floor_radius * c.pit.scale_xy;
      auto place = [&](double a) {
        const double reach = std::max(0.0, 0.9 * (floor_r - a - 4.0));
        double x = 0, y = 0;
        do {
          x = r.uniform(-1.0, 1.0);
          y = r.uniform(-1.0, 1.0);
        } while (x * x + y * y > 1.0);
        return std::pair<double, double>(q(reach * x), q(reach * y));
      };
      const double a = q(floor_r * r.uniform(0.15, 0.3));
      const double H = q(std::min(depth * r.uniform(0.08, 0.3), 1.2 * a));
      const auto at = place(a);
      c.pit.lumps.push_back({H, a, at.first, at.second});
      const int lumps = r.integer(0, 6);
      for (int i = 0; i < lumps; ++i) {
        const double la = q(floor_r * r.uniform(0.03, 0.1) + 2.0);
        const double lh = q(std::min(depth * r.uniform(0.01, 0.05) + 1.0, la));
        const auto lat = place(la);
        c.pit.lumps.push_back({lh, la, lat.first, lat.second});
      }
    } else if (k == "grooves") {
      const int n = r.integer(3, 10);
      for (int i = 0; i < n; ++i) {
        PitOptions::Groove g;
        g.z_mm = q(depth * r.uniform(0.1, 0.9));
        g.width_mm = q(std::min(r.uniform(3.0, 15.0), 0.1 * depth));
        g.depth_mm = q(std::min(r.uniform(2.0, 10.0), 0.05 * R));
        g.tilt_mm = q(r.uniform(0.0, 5.0));
        g.phase_rad = r.uniform(0.0, 2.0 * kPi);
        c.pit.grooves.push_back(g);
      }
    } else if (k == "tilted") {
      c.scan.min_tilt_deg = 25.0;
      c.scan.max_tilt_deg = 60.0;
    } else if (k == "arc") {
      c.scan.path_arc_deg = r.uniform(120.0, 330.0);
    } else if (k == "ground_tilt") {
      c.pit.ground_tilt_deg = r.uniform(1.0, 5.0);
      c.pit.ground_tilt_azimuth_rad = r.uniform(0.0, 2.0 * kPi);
    } else if (k == "sparse") {
      c.scan.target_points = static_cast<uint32_t>(std::max(20000.0, base * r.uniform(0.08, 0.25)));
    }
  }
  if (c.passes > 1 || c.copies > 1) c.twin = "";  // named below
  char name[160];
  std::snprintf(name, sizeof name, "s%llu-%03u-%s-%c-%s", (unsigned long long)seed, index,
                family_name(c.family), c.surround[0] == 'g' ? 'g' : (c.surround[0] == 'n' ? 'n' : 'c'),
                c.condition.c_str());
  c.name = name;
  if (c.passes > 1 || c.copies > 1) c.twin = c.name + "-1x";
  *out = c;
  return true;
}

EnvelopeCase envelope_twin(const EnvelopeCase &c) {
  EnvelopeCase t = c;
  t.name = c.name + "-1x";
  t.passes = 1;
  t.pass_points = 0;
  t.jitter_mm = 0;
  t.copies = 1;
  t.interleave = false;
  t.slip_mm[0] = t.slip_mm[1] = t.slip_mm[2] = 0;
  t.units = "mm";
  t.twin.clear();
  t.is_twin = true;
  t.twin_of = c.name;
  t.expect = "measure";
  return t;
}

ScanPlan envelope_plan(const EnvelopeCase &c, const Pit &pit) {
  ScanPlan plan;
  plan.copies = c.copies;
  plan.interleave = c.interleave;
  plan.unit = c.units;
  plan.unit_divisor = c.units == "cm" ? 10.0 : (c.units == "m" ? 1000.0 : 1.0);
  PlanPass first;
  first.scan = c.scan;
  if (c.passes > 1 && c.condition == "long") first.scan.target_points = c.pass_points;
  plan.passes.push_back(first);
  const double L = std::max(pit.max_radius_mm, pit.rim_z_mm);
  for (uint32_t k = 1; k < c.passes; ++k) {
    PlanPass p;
    p.scan = c.scan;
    p.scan.seed = pass_seed(c.scan.seed, k);
    p.scan.transform_seed = c.scan.seed;
    p.scan.target_points = c.pass_points;
    p.moved = true;
    if (c.jitter_mm > 0.0) {
      // Registration jitter: a translation and a turn about the pit's
      // middle, each moving points by about jitter_mm / sqrt(3) per axis.
      Rng r = stream(c.sweep_seed, c.index, kJitter + k);
      const double s = c.jitter_mm / 1.7320508075688772;
      for (double &d : p.d) d = s * r.gauss();
      const double w[3] = {0.5 * s / L * r.gauss(), 0.5 * s / L * r.gauss(), 0.5 * s / L * r.gauss()};
      const double n = std::sqrt(1.0 + w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      const double qw = 1.0 / n, qx = w[0] / n, qy = w[1] / n, qz = w[2] / n;
      const double M[9] = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy),
                           2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx),
                           2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)};
      for (int i = 0; i < 9; ++i) p.M[i] = M[i];
      p.c[2] = 0.5 * pit.rim_z_mm;
    }
    for (int i = 0; i < 3; ++i) p.d[i] += c.slip_mm[i];
    plan.passes.push_back(p);
  }
  return plan;
}

namespace {

std::string json_escape(const std::string &s) {
  std::string o;
  for (char ch : s) {
    if (ch == '"' || ch == '\\') o += '\\';
    o += ch;
  }
  return o;
}

std::string reproduce(const EnvelopeCase &c) {
  char b[256];
  std::snprintf(b, sizeof b, "pitvol-sim sweep --seed %llu --index %u --family %s --condition %s --out DIR",
                (unsigned long long)c.sweep_seed, c.index, family_name(c.family), c.condition.c_str());
  return b;
}

}  // namespace

std::string envelope_json(const EnvelopeCase &c, const Pit &pit, const WrittenPlan &w) {
  const double v = pit.volume_mm3 / 1000.0;
  std::string pp = "[";
  for (size_t i = 0; i < w.pass_points.size(); ++i)
    pp += (i ? ", " : "") + std::to_string(w.pass_points[i]);
  pp += "]";
  char b[2048];
  std::snprintf(
      b, sizeof b,
      "{\"case\": \"%s\", \"set\": \"sweep\", \"sweep_seed\": %llu, \"index\": %u, "
      "\"seeds\": \"%s\", \"family\": \"%s\", \"surround\": \"%s\", \"ground\": %s, "
      "\"condition\": \"%s\", \"size_class\": \"%s\", \"exact_volume_cm3\": %.6f, "
      "\"radius_mm\": %.3f, \"depth_mm\": %.3f, \"seed\": %llu, \"scan_seed\": %llu, "
      "\"noise_mm\": %.4f, \"tilt_deg\": %.4f, \"path_arc_deg\": %.3f, \"points\": %llu, "
      "\"passes\": %u, \"pass_points\": %s, \"jitter_mm\": %.3f, \"copies\": %u, "
      "\"copies_interleaved\": %s, \"slip_mm\": [%.4f, %.4f, %.4f], \"units\": \"%s\", "
      "\"measure_units\": null, \"units_note\": \"%s\", \"twin\": %s, \"twin_of\": %s, "
      "\"expect\": \"%s\", \"unseen_wall_share\": %.4f, \"rim_unseen_sectors\": %u, \"reproduce\": \"%s\", \"ply\": \"%s.ply\", "
      "\"params\": ",
      c.name.c_str(), (unsigned long long)c.sweep_seed, c.index,
      c.sweep_seed >= kFirstFreshSeed ? "fresh" : "tuning", family_name(c.family),
      c.surround.c_str(), c.ground ? "true" : "false", c.condition.c_str(), size_class(v), v,
      pit.max_radius_mm, pit.rim_z_mm, (unsigned long long)c.pit_seed,
      (unsigned long long)c.scan.seed, c.scan.noise_mm, w.scan.tilt_deg, c.scan.path_arc_deg,
      (unsigned long long)w.scan.points, c.passes, pp.c_str(), c.jitter_mm, c.copies,
      c.interleave ? "true" : "false", c.slip_mm[0], c.slip_mm[1], c.slip_mm[2], c.units.c_str(),
      c.units == "mm"
          ? "millimetres: pitvol measure's default"
          : "measure WITHOUT --units: the scan tests pitvol's guess of the unit (the truth is in cm3)",
      c.twin.empty() ? "null" : ("\"" + c.twin + "\"").c_str(),
      c.twin_of.empty() ? "null" : ("\"" + c.twin_of + "\"").c_str(), c.expect.c_str(),
      w.coverage.unseen_share, w.coverage.rim_unseen_sectors, json_escape(reproduce(c)).c_str(),
      c.name.c_str());
  // The pose: world = R * pit + t (pit frame: axis on z, floor near 0, rim
  // plane at depth_mm), millimetres, for levelled views of the scan.
  char pose[640];
  std::snprintf(pose, sizeof pose,
                "\"world_from_pit\": {\"R\": [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, "
                "%.17g, %.17g], \"t_mm\": [%.17g, %.17g, %.17g]}, ",
                w.R[0], w.R[1], w.R[2], w.R[3], w.R[4], w.R[5], w.R[6], w.R[7], w.R[8], w.t[0], w.t[1],
                w.t[2]);
  std::string head(b);
  const size_t at = head.rfind("\"params\": ");
  return head.substr(0, at) + pose + head.substr(at) + pit.params_json + "}";
}

std::string envelope_csv_header() {
  return "case,family,ground,seed,noise_mm,points,tilt_deg,exact_volume_cm3,set,stress,"
         "surround,condition,size_class,units,passes,copies,slip_mm,expect,twin,twin_of,"
         "sweep_seed,index,radius_mm,depth_mm,unseen_wall_share,path_arc_deg,reproduce";
}

std::string envelope_csv_row(const EnvelopeCase &c, const Pit &pit, const WrittenPlan &w) {
  const double v = pit.volume_mm3 / 1000.0;
  const double slip =
      std::sqrt(c.slip_mm[0] * c.slip_mm[0] + c.slip_mm[1] * c.slip_mm[1] + c.slip_mm[2] * c.slip_mm[2]);
  char b[1024];
  std::snprintf(b, sizeof b,
                "%s,%s,%d,%llu,%.4f,%llu,%.4f,%.6f,%s,%s,%s,%s,%s,%s,%u,%u,%s,%s,%s,%s,%llu,%u,"
                "%.3f,%.3f,%.4f,%.3f,%s",
                c.name.c_str(), family_name(c.family), int(c.ground), (unsigned long long)c.pit_seed,
                c.scan.noise_mm, (unsigned long long)w.scan.points, w.scan.tilt_deg, v,
                c.is_twin ? "sweep-twin" : "sweep", c.condition.c_str(), c.surround.c_str(),
                c.condition.c_str(), size_class(v), c.units.c_str(), c.passes, c.copies,
                fmt("%.3f", c.slip_mm[2] < 0 ? -slip : slip).c_str(), c.expect.c_str(),
                c.twin.c_str(), c.twin_of.c_str(), (unsigned long long)c.sweep_seed, c.index,
                pit.max_radius_mm, pit.rim_z_mm, w.coverage.unseen_share, c.scan.path_arc_deg,
                reproduce(c).c_str());
  return b;
}

}  // namespace pv::sim
