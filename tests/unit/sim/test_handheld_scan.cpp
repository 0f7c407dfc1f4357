// pv::sim::HandheldScan with real Embree ray casting against cups built
// here (surfaces of revolution with an exact radius), and, when the pit
// generator provides meshes, against every pit family.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <cstring>
#include <utility>
#include <vector>

#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"

#include "pv_cmocka.h"

namespace {

using pv::sim::Frame;
using pv::sim::HandheldScan;
using pv::sim::Mesh;
using pv::sim::Pit;
using pv::sim::ScanParams;

constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 110.0;  // cup radius
constexpr double kH = 290.0;  // cup depth, rim plane at z = kH
constexpr int kSeg = 1024;    // sag of the polygon: 110 (1 - cos(pi/1024)) = 5.2e-4 mm

// Surface of revolution of a profile (r, z) from the axis outwards/upwards,
// triangles counter-clockwise seen from outside the void (normals into the
// soil): for a profile direction d and the angular tangent t, n = t x d.
// Profile segments are split into pieces of at most 5 mm so the triangles
// stay compact (long slivers make a poor BVH).
Mesh revolve(const std::vector<std::pair<double, double>> &coarse) {
  std::vector<std::pair<double, double>> profile;
  for (size_t i = 0; i + 1 < coarse.size(); ++i) {
    const double dr = coarse[i + 1].first - coarse[i].first;
    const double dz = coarse[i + 1].second - coarse[i].second;
    const int n = std::max(1, static_cast<int>(std::ceil(std::sqrt(dr * dr + dz * dz) / 5.0)));
    for (int k = 0; k < n; ++k) {
      const double f = static_cast<double>(k) / n;
      profile.push_back({coarse[i].first + f * dr, coarse[i].second + f * dz});
    }
  }
  profile.push_back(coarse.back());
  Mesh m;
  const size_t np = profile.size();
  for (size_t i = 0; i < np; ++i)
    for (int j = 0; j < kSeg; ++j) {
      const double a = 2.0 * kPi * j / kSeg;
      m.xyz.push_back(static_cast<float>(profile[i].first * std::cos(a)));
      m.xyz.push_back(static_cast<float>(profile[i].first * std::sin(a)));
      m.xyz.push_back(static_cast<float>(profile[i].second));
    }
  auto id = [](size_t i, int j) { return static_cast<uint32_t>(i * kSeg + (j % kSeg)); };
  for (size_t i = 0; i + 1 < np; ++i)
    for (int j = 0; j < kSeg; ++j) {
      const uint32_t A = id(i, j), B = id(i + 1, j), C = id(i, j + 1), D = id(i + 1, j + 1);
      if (profile[i].first > 0.0) m.tri.insert(m.tri.end(), {A, C, B});
      if (profile[i + 1].first > 0.0) m.tri.insert(m.tri.end(), {B, C, D});
    }
  return m;
}

Pit cup_pit(bool ledge) {
  Pit p{};
  p.family = pv::sim::Family::Cylinder;
  p.ground = false;
  p.seed = 0;
  if (ledge)
    p.scanned = revolve({{0, 0}, {kR, 0}, {kR, 140}, {80, 140}, {80, 150}, {kR, 150}, {kR, kH}});
  else
    p.scanned = revolve({{0, 0}, {kR, 0}, {kR, kH}});
  p.rim_z_mm = kH;
  p.max_radius_mm = kR;
  p.volume_mm3 = kPi * kR * kR * kH;
  return p;
}

struct Pt {
  double x, y, z;
};

struct Run {
  std::vector<Frame> frames;
  std::vector<Pt> local;  // points mapped back to the pit frame
  size_t total = 0;
  double R[9], t[3], tilt;
};

Run scan(const Pit &pit, const ScanParams &p) {
  Run r;
  HandheldScan s(pit, p);
  Frame f;
  while (s.next(&f)) r.frames.push_back(f);
  s.transform(r.R, r.t);
  r.tilt = s.tilt_deg();
  for (const Frame &fr : r.frames)
    for (const pv_point_t &q : fr.points) {
      const double w[3] = {q.x_mm - r.t[0], q.y_mm - r.t[1], q.z_mm - r.t[2]};
      // pit = R^T (world - t)
      r.local.push_back({r.R[0] * w[0] + r.R[3] * w[1] + r.R[6] * w[2],
                         r.R[1] * w[0] + r.R[4] * w[1] + r.R[7] * w[2],
                         r.R[2] * w[0] + r.R[5] * w[1] + r.R[8] * w[2]});
    }
  r.total = r.local.size();
  return r;
}

ScanParams clean(uint64_t seed) {
  ScanParams p;
  p.seed = seed;
  p.noise_mm = 0.0;
  p.multipath_share = 0.0;
  p.stray_share = 0.0;
  p.max_tilt_deg = 0.0;
  return p;
}

double rad(const Pt &q) { return std::sqrt(q.x * q.x + q.y * q.y); }

bool on_cup(const Pt &q, double tol) {
  const double r = rad(q);
  const bool wall = std::fabs(r - kR) <= tol && q.z >= -tol && q.z <= kH + tol;
  const bool floor = std::fabs(q.z) <= tol && r <= kR + tol;
  return wall || floor;
}

void test_noise_free_on_surface(void **) {
  const Run r = scan(cup_pit(false), clean(7));
  assert_true(r.total >= 300000);
  assert_true(r.tilt == 0.0);
  assert_true(std::fabs(r.R[8] - 1.0) < 1e-12);
  size_t off = 0, floor = 0, upper = 0, thirds[3] = {0, 0, 0};
  double worst = 0.0;
  for (const Pt &q : r.local) {
    if (!on_cup(q, 1e-3)) {
      if (off < 5) print_message("  off surface: r %.6f z %.6f\n", rad(q), q.z);
      ++off;
    }
    if (std::fabs(q.z) < 1e-3) {
      ++floor;
    } else {
      worst = std::max(worst, std::fabs(rad(q) - kR));
      if (q.z >= 2.0 * kH / 3.0) ++upper;
      ++thirds[std::min(2, static_cast<int>(3.0 * q.z / kH))];
    }
  }
  const double floor_area = kPi * kR * kR;
  const double upper_area = 2.0 * kPi * kR * (kH / 3.0);
  const double d_floor = static_cast<double>(floor) / floor_area;
  const double d_upper = static_cast<double>(upper) / upper_area;
  print_message("  %zu points in %zu frames, worst wall |r-R| %.2e mm\n", r.total,
                r.frames.size(), worst);
  print_message("  density floor %.3f /mm2, upper third of wall %.3f /mm2 (%.1fx)\n", d_floor,
                d_upper, d_floor / std::max(d_upper, 1e-12));
  print_message("  wall thirds bottom..top: %.3f %.3f %.3f /mm2\n",
                static_cast<double>(thirds[0]) / upper_area,
                static_cast<double>(thirds[1]) / upper_area,
                static_cast<double>(thirds[2]) / upper_area);
  assert_int_equal(off, 0);
  assert_true(d_floor > 1.5 * d_upper);
  assert_true(upper > 0);  // sparse, not empty
}

void test_transform_inverts(void **) {
  ScanParams p = clean(11);
  p.max_tilt_deg = 25.0;
  const Run r = scan(cup_pit(false), p);
  // R orthonormal, its Z axis tilted by tilt_deg().
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double d = 0.0;
      for (int k = 0; k < 3; ++k) d += r.R[3 * k + i] * r.R[3 * k + j];
      assert_true(std::fabs(d - (i == j ? 1.0 : 0.0)) < 1e-12);
    }
  const double tilt = std::acos(std::min(1.0, r.R[8])) * 180.0 / kPi;
  print_message("  tilt %.3f deg (R: %.3f), offset %.1f %.1f %.1f\n", r.tilt, tilt, r.t[0],
                r.t[1], r.t[2]);
  assert_true(r.tilt >= 0.0 && r.tilt <= 25.0);
  assert_true(std::fabs(tilt - r.tilt) < 1e-6);
  for (int i = 0; i < 3; ++i) assert_true(std::fabs(r.t[i]) >= 100.0 && std::fabs(r.t[i]) <= 500.0);
  size_t off = 0;
  for (const Pt &q : r.local) off += on_cup(q, 1e-3) ? 0 : 1;
  assert_int_equal(off, 0);
  // Not level in the world: the raw floor points are not at one height.
  double zmin = 1e30, zmax = -1e30;
  for (const Frame &f : r.frames)
    for (const pv_point_t &q : f.points) {
      zmin = std::min(zmin, static_cast<double>(q.z_mm));
      zmax = std::max(zmax, static_cast<double>(q.z_mm));
    }
  assert_true(zmax - zmin > kH);
  // Tilts spread over [0, 25] (the transform needs no geometry).
  Pit no_hits = cup_pit(false);
  no_hits.scanned.tri.clear();
  double tmin = 90, tmax = 0;
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    ScanParams q = p;
    q.seed = seed;
    q.target_points = 1;
    HandheldScan s(no_hits, q);
    tmin = std::min(tmin, s.tilt_deg());
    tmax = std::max(tmax, s.tilt_deg());
  }
  print_message("  tilts over 40 seeds: %.2f .. %.2f deg\n", tmin, tmax);
  assert_true(tmin < 5.0 && tmax > 20.0 && tmax <= 25.0);
}

void test_target_and_frames(void **) {
  for (uint32_t target : {1000u, 200000u, 400000u}) {
    ScanParams p;
    p.seed = 3;
    p.target_points = target;
    p.frames_per_s = 20.0;
    const Run r = scan(cup_pit(false), p);
    assert_true(!r.frames.empty());
    const size_t last = r.frames.back().points.size();
    print_message("  target %u: %zu points in %zu frames (last %zu)\n", target, r.total,
                  r.frames.size(), last);
    assert_true(r.total >= target);
    assert_true(r.total - last < target);
    for (size_t i = 0; i < r.frames.size(); ++i) {
      assert_int_equal(r.frames[i].sequence, i);
      assert_int_equal(r.frames[i].timestamp_us, i * 50000u);
    }
  }
  // A scene that is never hit: the path ends, next() says so.
  Pit empty = cup_pit(false);
  empty.scanned.tri.clear();
  HandheldScan s(empty, clean(1));
  Frame f;
  size_t frames = 0, points = 0;
  while (s.next(&f)) {
    ++frames;
    points += f.points.size();
  }
  assert_true(frames > 0);
  assert_int_equal(points, 0);
  assert_false(s.next(&f));
}

bool same(const Run &a, const Run &b) {
  if (a.frames.size() != b.frames.size()) return false;
  for (size_t i = 0; i < a.frames.size(); ++i) {
    const Frame &x = a.frames[i], &y = b.frames[i];
    if (x.sequence != y.sequence || x.timestamp_us != y.timestamp_us ||
        x.points.size() != y.points.size())
      return false;
    if (!x.points.empty() &&
        std::memcmp(x.points.data(), y.points.data(), x.points.size() * sizeof(pv_point_t)) != 0)
      return false;
  }
  return std::memcmp(a.R, b.R, sizeof a.R) == 0 && std::memcmp(a.t, b.t, sizeof a.t) == 0;
}

void test_deterministic(void **) {
  ScanParams p;  // defaults: noise, multipath, strays, tilt all on
  p.seed = 42;
  p.target_points = 200000;
  const Pit pit = cup_pit(false);
  const Run a = scan(pit, p), b = scan(pit, p);
  assert_true(same(a, b));
  p.seed = 43;
  const Run c = scan(pit, p);
  assert_false(same(a, c));
}

void test_multipath_and_strays(void **) {
  ScanParams p = clean(5);
  p.multipath_share = 0.05;
  const Run r = scan(cup_pit(false), p);
  size_t mp = 0, outside = 0;
  for (const Pt &q : r.local) {
    if (on_cup(q, 1e-3)) continue;
    ++mp;
    if (!(rad(q) < kR && q.z > 0.0 && q.z < kH)) ++outside;
  }
  const double share = static_cast<double>(mp) / static_cast<double>(r.total);
  print_message("  multipath: %zu of %zu = %.4f (asked 0.05), %zu outside the void\n", mp,
                r.total, share, outside);
  assert_int_equal(outside, 0);
  assert_true(std::fabs(share - 0.05) < 0.005);

  // Strays: off the surface, in a box 2-3x the pit.
  ScanParams s = clean(5);
  s.stray_share = 0.01;
  const Run t = scan(cup_pit(false), s);
  size_t off = 0, far = 0;
  for (const Pt &q : t.local) {
    if (on_cup(q, 1e-3)) continue;
    ++off;
    if (rad(q) > kR || q.z < 0.0 || q.z > kH) ++far;
    assert_true(std::fabs(q.x) <= 3.0 * kR + 1e-3 && std::fabs(q.y) <= 3.0 * kR + 1e-3);
  }
  const double sshare = static_cast<double>(off) / static_cast<double>(t.total);
  print_message("  strays: %zu of %zu = %.4f (asked 0.01), %zu outside the pit\n", off, t.total,
                sshare, far);
  assert_true(std::fabs(sshare - 0.01) < 0.002);
  assert_true(far > off / 2);

  // Range noise: the radial spread of wall points matches sigma along rays.
  ScanParams n = clean(5);
  n.noise_mm = 0.2;
  const Run u = scan(cup_pit(false), n);
  double sum2 = 0.0, cnt = 0.0;
  for (const Pt &q : u.local)
    if (q.z > 5.0) {
      const double e = rad(q) - kR;
      assert_true(std::fabs(e) < 0.2 * 7.0);
      sum2 += e * e;
      cnt += 1.0;
    }
  print_message("  noise 0.2 mm: wall radial rms %.4f mm over %.0f points\n",
                std::sqrt(sum2 / cnt), cnt);
  assert_true(std::sqrt(sum2 / cnt) > 0.02 && std::sqrt(sum2 / cnt) < 0.2);
}

void test_ledge_shadow(void **) {
  const ScanParams p = clean(9);
  const Run plain = scan(cup_pit(false), p), ledge = scan(cup_pit(true), p);
  auto band = [](const Run &r) {
    size_t n = 0;
    for (const Pt &q : r.local)
      if (q.z >= 100.0 && q.z < 139.0 && std::fabs(rad(q) - kR) < 1e-3) ++n;
    return n;
  };
  const size_t a = band(plain), b = band(ledge);
  print_message("  wall band z 100..139: %zu points without the ledge, %zu with it\n", a, b);
  assert_true(a > 1000);
  assert_true(b * 4 < a);
  // Points on the ledge top exist; none on its underside (z = 140 from below
  // can only be reached through the soil).
  size_t top = 0, under = 0;
  for (const Pt &q : ledge.local) {
    if (std::fabs(q.z - 150.0) < 1e-3 && rad(q) > 80.0 && rad(q) < kR) ++top;
    if (std::fabs(q.z - 140.0) < 1e-3 && rad(q) > 80.0 && rad(q) < kR) ++under;
  }
  print_message("  ledge top %zu points, underside %zu\n", top, under);
  assert_true(top > 0);
  assert_int_equal(under, 0);
}

void test_speed(void **) {
  ScanParams p;
  p.seed = 1;
  p.target_points = 400000;
  const Pit pit = cup_pit(false);
  const auto tb = std::chrono::steady_clock::now();
  HandheldScan s(pit, p);
  const auto t0 = std::chrono::steady_clock::now();
  const double build = std::chrono::duration<double>(t0 - tb).count();
  const std::clock_t c0 = std::clock();
  Frame f;
  size_t points = 0, frames = 0;
  while (s.next(&f)) {
    points += f.points.size();
    ++frames;
  }
  const double np = static_cast<double>(points);
  const double sec =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const double rays = static_cast<double>(frames) * p.rays_x * p.rays_y;
  print_message("  %zu triangles: scene + path sizing %.3f s\n", pit.scanned.triangles(), build);
  print_message("  %zu points, %zu frames in %.3f s wall, %.3f s cpu: %.2f Mpoints/s, "
                "%.2f Mrays/s (cpu)\n",
                points, frames, sec, cpu, np / cpu * 1e-6, rays / cpu * 1e-6);
  assert_true(points >= p.target_points);
}

// The path is sized from the pit: the target is reached from 15 cm x 40 cm
// deep to 40 cm x 10 cm, with and without a ground ring.
void test_pit_sizes(void **) {
  const double dims[][2] = {{75, 400}, {110, 290}, {200, 100}};
  for (const auto &d : dims)
    for (bool ground : {false, true}) {
      Pit pit{};
      pit.family = pv::sim::Family::Cylinder;
      pit.ground = ground;
      std::vector<std::pair<double, double>> prof = {{0, 0}, {d[0], 0}, {d[0], d[1]}};
      if (ground) prof.push_back({2.5 * d[0], d[1]});
      pit.scanned = revolve(prof);
      pit.rim_z_mm = d[1];
      pit.max_radius_mm = d[0];
      pit.ground_outer_radius_mm = ground ? 2.5 * d[0] : 0.0;
      for (uint32_t target : {200000u}) {
        ScanParams p;
        p.seed = 77;
        p.target_points = target;
        const Run r = scan(pit, p);
        const size_t last = r.frames.back().points.size();
        size_t on_ground = 0;
        for (const Pt &q : r.local) on_ground += std::fabs(q.z - d[1]) < 1.0 ? 1 : 0;
        print_message("  r %3.0f depth %3.0f ground %d target %u: %zu points in %zu frames "
                      "(%zu near the rim plane)\n",
                      d[0], d[1], ground ? 1 : 0, target, r.total, r.frames.size(), on_ground);
        assert_true(r.total >= target);
        assert_true(r.total - last < target);
        // Well inside one pass (4 loops sized to 1.3 x target): the scan
        // spends most of it.
        assert_true(r.frames.size() >= 40);
      }
    }
}

#ifndef PV_SIM_TEST_NO_MAKE_PIT
void test_all_families(void **) {
  const int n = static_cast<int>(pv::sim::Family::kCount);
  for (int fi = 0; fi < n; ++fi)
    for (bool ground : {false, true}) {
      const auto fam = static_cast<pv::sim::Family>(fi);
      // With a ground ring: the two extreme sizes only (test time).
      if (ground && fam != pv::sim::Family::ShallowWide && fam != pv::sim::Family::DeepNarrow)
        continue;
      const Pit pit = pv::sim::make_pit(fam, ground, 1);
      if (pit.scanned.tri.empty()) {  // generator not there yet
        print_message("  %s: no mesh, skipped\n", pv::sim::family_name(fam));
        continue;
      }
      ScanParams p;
      p.seed = 100 + static_cast<uint64_t>(fi);
      p.target_points = 200000;
      HandheldScan s(pit, p);
      Frame f;
      size_t points = 0, frames = 0, last = 0;
      while (s.next(&f)) {
        points += f.points.size();
        last = f.points.size();
        ++frames;
      }
      print_message("  %-12s ground %d: r %.0f rim %.0f: %zu points in %zu frames\n",
                    pv::sim::family_name(fam), ground ? 1 : 0, pit.max_radius_mm, pit.rim_z_mm,
                    points, frames);
      assert_true(points >= p.target_points);
      assert_true(points - last < p.target_points);
    }
}
#endif

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_noise_free_on_surface),
      cmocka_unit_test(test_transform_inverts),
      cmocka_unit_test(test_target_and_frames),
      cmocka_unit_test(test_deterministic),
      cmocka_unit_test(test_multipath_and_strays),
      cmocka_unit_test(test_ledge_shadow),
      cmocka_unit_test(test_speed),
      cmocka_unit_test(test_pit_sizes),
#ifndef PV_SIM_TEST_NO_MAKE_PIT
      cmocka_unit_test(test_all_families),
#endif
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
