// The three corpus sets (standard, holdout, stress) and the stress options
// of the scan simulator: the standard set pinned bit for bit (its list, two
// of its pits, the start of one scan), the holdout set disjoint from it, every
// stress case buildable with its exact truth, and real Embree scans showing
// each stress option does what it says (dropout patches return nothing, a
// partial path leaves a side unseen, a tilted ground ring is still seen).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "sim/corpus.h"
#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"

#include "pv_cmocka.h"

namespace {

using pv::sim::CorpusCase;
using pv::sim::Family;
using pv::sim::Frame;
using pv::sim::HandheldScan;
using pv::sim::Pit;
using pv::sim::PitOptions;
using pv::sim::ScanParams;

constexpr double kPi = 3.14159265358979323846;

// FNV-1a 64 over bytes.
struct Fnv {
  uint64_t h = 0xcbf29ce484222325ull;
  void add(const void *p, size_t n) {
    const auto *b = static_cast<const unsigned char *>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  }
  void str(const std::string &s) { add(s.data(), s.size()); }
};

std::string describe(const CorpusCase &c) {
  char b[256];
  std::snprintf(b, sizeof b, "%s|%d|%d|%llu|%llu|%.17g|%u|%.17g|%u;", c.name.c_str(),
                static_cast<int>(c.family), int(c.ground), (unsigned long long)c.seed,
                (unsigned long long)c.scan.seed, c.scan.noise_mm, unsigned(c.scan.target_points),
                c.scan.path_arc_deg, unsigned(c.scan.dropout_patches));
  return b;
}

// ---------------------------------------------------------------------------
// The standard set stays what tests/corpus/expected.csv was recorded on:
// its case list, two of its pits and the first frames of one scan are
// pinned, so a change to the generator for other sets cannot move it.

void test_standard_list_pinned(void **) {
  const auto cases = pv::sim::standard_corpus();
  assert_int_equal(cases.size(), 33);
  Fnv h;
  for (const CorpusCase &c : cases) {
    h.str(describe(c));
    assert_string_equal(c.set.c_str(), "standard");
    assert_string_equal(c.stress.c_str(), "none");
    // Defaults: nothing of the stress options.
    assert_true(c.pit.ground_tilt_deg == 0 && c.pit.depth_mm == 0 && c.pit.stone_height_mm == 0);
    assert_true(c.scan.target_points == 300000 && c.scan.path_arc_deg == 360.0 &&
                c.scan.dropout_patches == 0);
  }
  assert_string_equal(cases[0].name.c_str(), "cylinder-g-1");
  assert_string_equal(cases[32].name.c_str(), "deep_narrow-g-3");
  assert_true(cases[24].family == Family::HandDug && cases[24].scan.seed == 8001 &&
              cases[24].scan.noise_mm == 0.02);
  print_message("standard list hash %016llx\n", (unsigned long long)h.h);
  assert_true(h.h == 0x1ebdb619f2cfbd25ull);
}

void mesh_hash(const Pit &p, Fnv *h) {
  h->add(p.scanned.xyz.data(), p.scanned.xyz.size() * sizeof(float));
  h->add(p.scanned.tri.data(), p.scanned.tri.size() * sizeof(uint32_t));
  h->add(p.void_closed.xyz.data(), p.void_closed.xyz.size() * sizeof(float));
  h->add(p.void_closed.tri.data(), p.void_closed.tri.size() * sizeof(uint32_t));
  h->add(&p.volume_mm3, sizeof p.volume_mm3);
  h->str(p.params_json);
}

void test_standard_pits_pinned(void **) {
  const Pit cyl = pv::sim::make_pit(Family::Cylinder, true, 1);
  const Pit dug = pv::sim::make_pit(Family::HandDug, true, 1);
  Fnv a, b;
  mesh_hash(cyl, &a);
  mesh_hash(dug, &b);
  print_message("cylinder-g-1 V %a mm3 hash %016llx; hand_dug-g-1 V %a hash %016llx\n",
                cyl.volume_mm3, (unsigned long long)a.h, dug.volume_mm3, (unsigned long long)b.h);
  // The volumes as in the corpus manifest (10675.597949 cm3 ...), exactly.
  assert_true(cyl.volume_mm3 == 0x1.45cb1be5c10d7p+23);
  assert_true(dug.volume_mm3 == 0x1.2f3aac1d92b19p+23);
  assert_true(a.h == 0xdabf4eb6f3692afdull);
  assert_true(b.h == 0x39c29a3ab6ab918bull);
}

// The first frames of the standard scan cylinder-g-1, pinned: the same
// bytes on every x86-64, whatever Embree's kernels (run again with
// PITVOL_SIM_ISA=sse2 and avx2) and glibc's libm variant (run again under
// qemu-x86_64 as an SSE2-only CPU: sim_same_bits.sh).
void test_standard_scan_pinned(void **) {
  const CorpusCase c = pv::sim::standard_corpus()[0];
  const Pit pit = pv::sim::make_pit(c.family, c.ground, c.seed, c.pit);
  HandheldScan s(pit, c.scan);
  Frame f;
  Fnv h;
  size_t n = 0;
  for (int i = 0; i < 8 && s.next(&f); ++i) {
    h.add(f.points.data(), f.points.size() * sizeof(pv_point_t));
    n += f.points.size();
  }
  print_message("cylinder-g-1: first 8 frames %zu points, hash %016llx\n", n,
                (unsigned long long)h.h);
  assert_int_equal(n, 21673);
  assert_true(h.h == 0x87fcccaa1ecf31bdull);
  assert_true(s.dropout_patches().empty());
}

// ---------------------------------------------------------------------------
// Holdout: the same composition, nothing shared.

void test_holdout_disjoint(void **) {
  const auto std_cases = pv::sim::standard_corpus();
  const auto hold = pv::sim::holdout_corpus();
  assert_int_equal(hold.size(), std_cases.size());
  std::set<std::string> names;
  std::set<uint64_t> pit_seeds, scan_seeds;
  for (const CorpusCase &c : std_cases) {
    names.insert(c.name);
    pit_seeds.insert(c.seed);
    scan_seeds.insert(c.scan.seed);
  }
  int ground = 0;
  for (size_t i = 0; i < hold.size(); ++i) {
    const CorpusCase &c = hold[i];
    assert_true(c.family == std_cases[i].family);  // same families, same order
    assert_string_equal(c.set.c_str(), "holdout");
    assert_true(names.count(c.name) == 0);
    assert_true(pit_seeds.count(c.seed) == 0);
    assert_true(scan_seeds.count(c.scan.seed) == 0);
    assert_true(c.scan.target_points == 300000 && c.scan.path_arc_deg == 360.0 &&
                c.scan.dropout_patches == 0 && c.pit.stone_height_mm == 0);
    assert_true(c.scan.noise_mm >= 0.02 && c.scan.noise_mm <= 0.2);
    ground += c.ground;
  }
  assert_int_equal(ground, 11 + 5);  // every family once, the third case of odd families
  // Different pits, not only different names.
  const Pit a = pv::sim::make_pit(hold[0].family, hold[0].ground, hold[0].seed);
  const Pit b = pv::sim::make_pit(std_cases[0].family, std_cases[0].ground, std_cases[0].seed);
  assert_true(a.volume_mm3 != b.volume_mm3);
  std::vector<CorpusCase> by;
  assert_true(pv::sim::corpus_by_name("holdout", &by) && by.size() == 33);
  assert_false(pv::sim::corpus_by_name("tuning", &by));
}

// ---------------------------------------------------------------------------
// Stress: every case builds, with its exact truth.

void test_stress_cases(void **) {
  const auto cases = pv::sim::stress_corpus();
  std::set<std::string> names, kinds;
  for (const CorpusCase &c : cases) {
    assert_true(names.insert(c.name).second);
    kinds.insert(c.stress);
    assert_string_equal(c.set.c_str(), "stress");
    assert_true(c.name.rfind(c.stress + "-", 0) == 0);
    const Pit p = pv::sim::make_pit(c.family, c.ground, c.seed, c.pit);
    assert_true(p.volume_mm3 > 0 && p.volume_mm3 == pv::sim::signed_volume_mm3(p.void_closed));
    if (c.stress == "stone") {
      const Pit bare = pv::sim::make_pit(c.family, c.ground, c.seed);
      const double stone = pv::sim::stone_volume_mm3(c.pit.stone_height_mm, c.pit.stone_radius_mm);
      print_message("%s: %.3f cm3 = %.3f - stone %.3f\n", c.name.c_str(), p.volume_mm3 / 1e3,
                    bare.volume_mm3 / 1e3, stone / 1e3);
      assert_true(std::fabs(bare.volume_mm3 - p.volume_mm3 - stone) < 1e-4 * stone);
    }
    if (c.stress == "depth_capacity") assert_true(p.rim_z_mm >= 560 && p.rim_z_mm < 640);
    if (c.stress == "tilted_ground") assert_true(c.pit.ground_tilt_deg >= 2 && c.ground);
    if (c.stress == "sparse") assert_int_equal(c.scan.target_points, 30000);
    if (c.stress == "dense") assert_int_equal(c.scan.target_points, 2000000);
    if (c.stress == "one_side") assert_true(c.scan.path_arc_deg <= 180);
    if (c.stress == "dropout") assert_true(c.scan.dropout_patches >= 4);
  }
  const std::set<std::string> want = {"one_side", "sparse",  "dense",         "tilted_ground",
                                      "dropout",  "stone",   "depth_capacity"};
  assert_true(kinds == want);
}

// ---------------------------------------------------------------------------
// The stress options in real scans.

struct Local {
  double x, y, z;
};

std::vector<Local> scan_local(const Pit &pit, const ScanParams &p, HandheldScan **keep = nullptr) {
  auto *s = new HandheldScan(pit, p);
  Frame f;
  std::vector<pv_point_t> pts;
  while (s->next(&f)) pts.insert(pts.end(), f.points.begin(), f.points.end());
  double R[9], t[3];
  s->transform(R, t);
  std::vector<Local> out;
  for (const pv_point_t &q : pts) {
    const double w[3] = {q.x_mm - t[0], q.y_mm - t[1], q.z_mm - t[2]};
    out.push_back({R[0] * w[0] + R[3] * w[1] + R[6] * w[2], R[1] * w[0] + R[4] * w[1] + R[7] * w[2],
                   R[2] * w[0] + R[5] * w[1] + R[8] * w[2]});
  }
  if (keep) *keep = s;
  else delete s;
  return out;
}

ScanParams clean(uint64_t seed, uint32_t target) {
  ScanParams p;
  p.seed = seed;
  p.target_points = target;
  p.noise_mm = 0.0;
  p.multipath_share = 0.0;
  p.stray_share = 0.0;
  return p;
}

void test_dropout_patches(void **) {
  const Pit pit = pv::sim::make_pit(Family::Cylinder, false, 1);
  const double R = pit.max_radius_mm;
  ScanParams p = clean(31, 80000);
  p.dropout_patches = 8;
  HandheldScan *s = nullptr;
  const std::vector<Local> with = scan_local(pit, p, &s);
  const std::vector<pv::sim::DropoutPatch> patches = s->dropout_patches();
  delete s;
  assert_int_equal(patches.size(), 8);
  size_t wall = 0;
  for (const auto &d : patches) {
    const double r = std::hypot(d.x_mm, d.y_mm);
    const bool on_wall = std::fabs(r - R) < 1e-2 && d.z_mm >= 0 && d.z_mm <= pit.rim_z_mm;
    const bool on_floor = std::fabs(d.z_mm) < 1e-4 && r <= R;
    assert_true(on_wall || on_floor);
    wall += on_wall;
    assert_true(d.radius_mm >= 20.0 && d.radius_mm <= 40.0);
  }
  auto inside = [&](const Local &q) {
    for (const auto &d : patches) {
      const double dx = q.x - d.x_mm, dy = q.y - d.y_mm, dz = q.z - d.z_mm;
      if (dx * dx + dy * dy + dz * dz < d.radius_mm * d.radius_mm - 1e-3) return true;
    }
    return false;
  };
  size_t in_with = 0, in_without = 0;
  for (const Local &q : with) in_with += inside(q);
  p.dropout_patches = 0;
  const std::vector<Local> without = scan_local(pit, p);
  for (const Local &q : without) in_without += inside(q);
  print_message("dropout: %zu patches (%zu on the wall); points inside them: %zu with, %zu "
                "without (of %zu, %zu)\n", patches.size(), wall, in_with, in_without,
                with.size(), without.size());
  assert_int_equal(in_with, 0);
  assert_true(in_without > 1000);
  assert_true(with.size() >= 80000);  // the target is still reached
}

// Wall points per 30 deg sector (pit frame), smallest / largest.
double sector_ratio(const std::vector<Local> &pts, double R, double rim, std::vector<size_t> *bins) {
  bins->assign(12, 0);
  for (const Local &q : pts) {
    if (std::fabs(std::hypot(q.x, q.y) - R) > 1e-2 || q.z < 1.0 || q.z > rim) continue;
    const double a = std::atan2(q.y, q.x) + kPi;
    (*bins)[std::min<size_t>(11, static_cast<size_t>(a / (kPi / 6)))]++;
  }
  const auto mm = std::minmax_element(bins->begin(), bins->end());
  return static_cast<double>(*mm.first) / static_cast<double>(std::max<size_t>(1, *mm.second));
}

void test_partial_path(void **) {
  const Pit pit = pv::sim::make_pit(Family::Cylinder, false, 1);
  ScanParams p = clean(32, 100000);
  std::vector<size_t> full_bins, arc_bins;
  const double full = sector_ratio(scan_local(pit, p), pit.max_radius_mm, pit.rim_z_mm, &full_bins);
  p.path_arc_deg = 90.0;
  const double arc = sector_ratio(scan_local(pit, p), pit.max_radius_mm, pit.rim_z_mm, &arc_bins);
  std::string fb, ab;
  for (size_t i = 0; i < 12; ++i) {
    fb += " " + std::to_string(full_bins[i]);
    ab += " " + std::to_string(arc_bins[i]);
  }
  print_message("wall points per 30 deg, full path:%s (min/max %.3f)\n", fb.c_str(), full);
  print_message("wall points per 30 deg, 90 deg arc:%s (min/max %.4f)\n", ab.c_str(), arc);
  assert_true(full > 0.3);
  assert_true(arc < 0.02);
  // Not a whole half empty: the far side is seen.
  size_t seen = 0;
  for (size_t b : arc_bins) seen += b > full_bins[0] / 4;
  assert_true(seen >= 3);
}

void test_tilted_ground_seen(void **) {
  PitOptions o;
  o.ground_tilt_deg = 4.0;
  o.ground_tilt_azimuth_rad = 1.0;
  const Pit pit = pv::sim::make_pit(Family::Cylinder, true, 1, o);
  const double gx = std::tan(4.0 * kPi / 180) * std::cos(1.0);
  const double gy = std::tan(4.0 * kPi / 180) * std::sin(1.0);
  const std::vector<Local> pts = scan_local(pit, clean(33, 80000));
  size_t ground = 0, off = 0, high = 0;
  for (const Local &q : pts) {
    if (std::hypot(q.x, q.y) < pit.max_radius_mm + 0.5) continue;
    ++ground;
    const double dz = q.z - (pit.rim_z_mm + gx * q.x + gy * q.y);
    if (std::fabs(dz) > 1e-3) ++off;
    if (q.z > pit.rim_z_mm + 5.0) ++high;
  }
  print_message("tilted ground: %zu of %zu points on the ring, %zu off its plane, %zu more "
                "than 5 mm above the rim height\n", ground, pts.size(), off, high);
  assert_true(ground > 2000);
  assert_int_equal(off, 0);
  assert_true(high > 100);
}

}  // namespace

// argv[1]: optional cmocka test filter ("*pinned*": the pins alone).
int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_standard_list_pinned),
      cmocka_unit_test(test_standard_pits_pinned),
      cmocka_unit_test(test_standard_scan_pinned),
      cmocka_unit_test(test_holdout_disjoint),
      cmocka_unit_test(test_stress_cases),
      cmocka_unit_test(test_dropout_patches),
      cmocka_unit_test(test_partial_path),
      cmocka_unit_test(test_tilted_ground_seen),
  };
  if (argc > 1) cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
