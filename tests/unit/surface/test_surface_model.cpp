// pv::surface (method "surface") against pits of exactly known volume built
// from points: cylinder, cone frustum, elliptical cylinder, a bowl (sphere
// cap), a cylinder with multipath inside, one with a band of wall removed
// (bridged, inside the interval), one with multipath under a neck where the
// wall is hidden (not wall); and with the MCU profile's coarse
// bins and few points (Params::coarse_bins): an ellipse and a bowl.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "surface/surface_model.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::surface::Point;
using pv::test::kPi;
using pv::test::Rng;

// r_of(theta, z) gives the wall; the floor is flat at z = 0 unless a bowl.
struct Pit {
  double a = 100, b = 100;      // semi-axes at z = 0
  double taper = 0;             // radius grows by taper * z
  double bulge = 0;             // radius grows by bulge * sin(pi z / depth)
  double top_mm = 60;           // the flat ring at the rim: a ground's width
  bool outer_wall = false;      // a vessel: a wall at the top's outer edge
  double depth = 200;
  double bowl_radius = 0;       // > 0: the floor is a sphere cap of this radius
  double gap_from = -1, gap_to = -1;  // wall band with no points
  double multipath = 0;         // share of points floating inside
  // A neck: the wall stands neck_mm further in over [neck_from, neck_to);
  // the wall under it over [hidden_from, neck_from) is hidden, and in its
  // place fog_points points float at neck_mm + 5 to neck_mm + 55 mm inside
  // the wall (multipath of the floor seen through the neck).
  double neck_mm = 0, neck_from = 0, neck_to = 0, hidden_from = 0;
  int fog_points = 0;
  double keep_wall = 1, keep_floor = 1;  // share of the points kept (the MCU's few)
  // A wet patch: no point, wall or floor, at a horizontal radius in
  // [patch_r0, patch_r1) and an angle in [0, patch_th) rad.
  double patch_r0 = 0, patch_r1 = 0, patch_th = 0;
  bool in_patch(double th, double r) const {
    const double ang = th < 0 ? th + 2 * kPi : th;
    return r >= patch_r0 && r < patch_r1 && ang < patch_th;
  }
  double rw(double th, double z) const {
    if (bowl_radius > 0 && z < bowl_radius) {
      const double R = bowl_radius;
      return std::sqrt(std::max(0.0, R * R - (R - z) * (R - z)));
    }
    const double s = 1 + taper * z / a;
    const double out = bulge * std::sin(kPi * std::min(z, depth) / depth) -
                       (z >= neck_from && z < neck_to ? neck_mm : 0.0);
    return out + s * a * b / std::sqrt(std::pow(b * std::cos(th), 2) + std::pow(a * std::sin(th), 2));
  }
};

std::vector<Point> points_of(const Pit &p, uint64_t seed) {
  Rng rng{seed};
  std::vector<Point> v;
  const double noise = 0.05;
  for (double z = 0.25; z < p.depth + 3; z += 0.5) {
    if (z >= p.gap_from && z < p.gap_to) continue;
    if (z >= p.hidden_from && z < p.neck_from) continue;
    for (int k = 0; k < 720; ++k) {
      const double th = (k + rng.uniform()) * 2 * kPi / 720;
      double r = p.rw(th, z) + noise * rng.gauss();
      if (p.keep_wall < 1 && !(rng.uniform() < p.keep_wall)) continue;
      if (p.in_patch(th, r)) continue;
      if (z > p.depth) r += p.top_mm * rng.uniform();  // ground ring, above the rim
      const double zz = std::min(z, p.depth) + (z > p.depth ? 0.0 : 0.0);
      v.push_back(Point{r * std::cos(th), r * std::sin(th), zz});
      if (p.outer_wall && z <= p.depth) {
        const double ro = p.rw(th, p.depth) + p.top_mm + noise * rng.gauss();
        v.push_back(Point{ro * std::cos(th), ro * std::sin(th), z});
      }
      if (rng.uniform() < p.multipath) {
        const double f = 0.3 + 0.6 * rng.uniform();
        v.push_back(Point{f * r * std::cos(th), f * r * std::sin(th), zz});
      }
    }
  }
  for (int k = 0; k < p.fog_points; ++k) {
    const double th = rng.uniform() * 2 * kPi, z = p.hidden_from + (p.neck_from - p.hidden_from) * rng.uniform();
    const double r = p.rw(th, z) - p.neck_mm - 5 - 50 * rng.uniform();
    v.push_back(Point{r * std::cos(th), r * std::sin(th), z});
  }
  // Floor: a dense grid inside the z = 0 outline.
  for (double x = -200; x <= 200; x += 1.0) {
    for (double y = -200; y <= 200; y += 1.0) {
      const double th = std::atan2(y, x), r = std::hypot(x, y);
      double z = noise * rng.gauss();
      if (p.keep_floor < 1 && !(rng.uniform() < p.keep_floor)) continue;
      if (p.in_patch(th, r)) continue;
      if (p.bowl_radius > 0) {
        const double R = p.bowl_radius;
        if (r >= R) continue;
        z = R - std::sqrt(R * R - r * r);
        if (z > p.depth) continue;
      } else if (r >= p.rw(th, 0)) {
        continue;
      }
      v.push_back(Point{x, y, z});
    }
  }
  return v;
}

void visit(void *ctx, pv::surface::PointFn fn, void *fn_ctx) {
  const auto &v = *static_cast<std::vector<Point> *>(ctx);
  // Uneven batches: a pass must not depend on where a batch ends.
  for (size_t i = 0; i < v.size();) {
    const size_t n = std::min<size_t>(1 + i % 300, v.size() - i);
    fn(fn_ctx, v.data() + i, n);
    i += n;
  }
}

struct Measured {
  pv::surface::Volume v;
  double unseen_share;
};

// z_bottom_mm, floor: as pv::surface::build() takes them.
Measured measure(std::vector<Point> &pts, double rim_mm,
                 const pv::surface::Params &prm = pv::surface::Params{},
                 pv::surface::Model *model = nullptr, double z_bottom_mm = -4.0,
                 const pv::surface::FloorPlane &floor = pv::surface::FloorPlane{}) {
  const pv::surface::Capacity cap = pv::surface::capacity_for(prm, 400, 320);
  const size_t bytes = pv::surface::bytes_needed(cap);
  void *mem = std::aligned_alloc(64, (bytes + 63) / 64 * 64);
  pv::surface::Workspace ws;
  pv::surface::make_workspace(mem, cap, &ws);
  pv::surface::Model m;
  const pv::surface::PointSource src{&pts, visit};
  assert_int_equal(int(pv::surface::build(src, z_bottom_mm, rim_mm, prm, ws, &m, floor)),
                   int(pv::surface::Status::Ok));
  Measured r{pv::surface::integrate(ws, m, prm), 0};
  r.unseen_share = r.v.unseen_mm3 / r.v.volume_mm3;
  if (model != nullptr) *model = m;
  std::free(mem);
  return r;
}

void expect_within(double v, double truth, double rel) {
  const double e = (v - truth) / truth;
  if (std::fabs(e) > rel) fail_msg("volume %.1f mm3, truth %.1f mm3: %.4f %% off", v, truth, 100 * e);
}

void cylinder_volume_is_exact(void **) {
  Pit p;
  auto pts = points_of(p, 1);
  const Measured r = measure(pts, p.depth);
  expect_within(r.v.volume_mm3, kPi * 100 * 100 * p.depth, 0.001);
  assert_true(r.unseen_share < 0.01);
}

// A cylinder dug into a slope, levelled on its ground: the floor is a ramp
// z = kRampSlope * x from -10.5 to +10.5 mm, and sparse (a point per 2 mm
// cell on average, as the floor store keeps a wide pit's). The void over
// the ramp is the cylinder's whole section times the depth at the axis.
const double kRampSlope = std::tan(4.0 * kPi / 180);
constexpr double kRampRadius = 150, kRampDepth = 200;
constexpr double kRampTruth = kPi * kRampRadius * kRampRadius * kRampDepth;
double ramp_volume(const pv::surface::FloorPlane &given, uint64_t seed) {
  const double R = kRampRadius, D = kRampDepth, slope = kRampSlope;
  Rng rng{seed};
  std::vector<Point> v;
  for (int k = 0; k < 720; ++k) {
    const double th = (k + rng.uniform()) * 2 * kPi / 720;
    const double foot = slope * R * std::cos(th);
    for (double z = foot + 0.25; z < D + 3; z += 0.5) {
      double r = R + 0.05 * rng.gauss();
      if (z > D) r += 60 * rng.uniform();  // the ground ring
      v.push_back(Point{r * std::cos(th), r * std::sin(th), std::min(z, D)});
    }
  }
  for (double x = -R; x <= R; x += 1.0) {
    for (double y = -R; y <= R; y += 1.0) {
      if (std::hypot(x, y) >= R || !(rng.uniform() < 0.25)) continue;
      v.push_back(Point{x, y, slope * x + 0.05 * rng.gauss()});
    }
  }
  // The ramp's low end lies 10.5 mm under z = 0: the grid from 40 mm under
  // it, as the session keeps (gridding::kSurfaceBelowMm).
  return measure(v, D, pv::surface::Params{}, nullptr, -40.0, given).v.volume_mm3;
}

void ramp_floor_floods_from_its_plane(void **) {
  const double truth = kRampTruth;
  const double v = ramp_volume(pv::surface::FloorPlane{kRampSlope, 0, 0}, 21);
  print_message("ramp floor with its plane: %+.3f %%\n", 100 * (v - truth) / truth);
  expect_within(v, truth, 0.002);
}

// Without the plane, seeded at its lowest cells, the sparse ramp's flood
// stops short: the test above can fail.
void ramp_floor_without_its_plane_reads_low(void **) {
  const double truth = kRampTruth;
  const double v = ramp_volume(pv::surface::FloorPlane{}, 21);
  print_message("ramp floor without: %+.3f %%\n", 100 * (v - truth) / truth);
  if (!(v < truth * (1 - 0.004))) fail_msg("%.4f %% off", 100 * (v - truth) / truth);
}

void frustum_volume_is_exact(void **) {
  Pit p;
  p.a = p.b = 80;
  p.taper = 0.2;
  auto pts = points_of(p, 2);
  const double r1 = 80, r2 = 80 + 0.2 * p.depth;
  expect_within(measure(pts, p.depth).v.volume_mm3,
                kPi * p.depth / 3 * (r1 * r1 + r1 * r2 + r2 * r2), 0.0015);
}

void ellipse_volume_is_exact(void **) {
  Pit p;
  p.a = 130;
  p.b = 70;
  auto pts = points_of(p, 3);
  expect_within(measure(pts, p.depth).v.volume_mm3, kPi * 130 * 70 * p.depth, 0.001);
}

// A cylinder of radius 100 whose floor is a sphere cap of radius 100 (a
// hemisphere 100 deep under a cylinder): V = pi R^2 (H - R) + 2/3 pi R^3.
void bowl_volume_is_exact(void **) {
  Pit p;
  p.bowl_radius = 100;
  auto pts = points_of(p, 4);
  const double truth = kPi * 100 * 100 * (p.depth - 100) + 2.0 / 3.0 * kPi * 1e6;
  expect_within(measure(pts, p.depth).v.volume_mm3, truth, 0.001);
}

// The same bowl with a wet patch on its slope (no point, wall or floor, 45
// to 85 mm from the axis over 70 deg): beyond it the slope rises more than
// the flood's step, so no floor is seen between the patch and the wall,
// and the floor is carried flat to the wall under wall bins bridged far
// out (+0.56 %). The truth lies within the interval's terms: the bridge's
// bounds, the floor holes' (Volume::floor_hole_mm3: the hole open to the
// wall, +/-0.48 % before it) and the 0.1 %.
void bowl_floor_hole_within_interval(void **) {
  Pit p;
  p.bowl_radius = 100;
  p.patch_r0 = 45;
  p.patch_r1 = 85;
  p.patch_th = 70 * kPi / 180;
  auto pts = points_of(p, 4);
  const double truth = kPi * 100 * 100 * (p.depth - 100) + 2.0 / 3.0 * kPi * 1e6;
  const Measured r = measure(pts, p.depth);
  const double bridge = std::max(r.v.hi_mm3 - r.v.volume_mm3, r.v.volume_mm3 - r.v.lo_mm3);
  const double interval = bridge + r.v.floor_hole_mm3 + 0.001 * truth;
  std::printf("bowl with a patch: %.1f mm3 (%+.3f %%), interval %.3f %% (floor holes %.3f %%)\n",
              r.v.volume_mm3, 100 * (r.v.volume_mm3 / truth - 1), 100 * interval / truth,
              100 * r.v.floor_hole_mm3 / truth);
  assert_true(r.v.floor_hole_mm3 > 0);
  if (!(std::fabs(r.v.volume_mm3 - truth) <= interval)) {
    fail_msg("%.1f mm3 +/- %.1f, truth %.1f", r.v.volume_mm3, interval, truth);
  }
}

// A bulge reaching 80 mm further out under its rim than the 60 mm ground
// ring around it: the ring caps nothing (nothing stands behind a ground),
// where capped from the ring's outer edge the bulge lost what lies beyond
// it (-11.8 %). V = pi (a^2 D + 4 a B D / pi + B^2 D / 2).
void ground_ring_caps_no_bulge(void **) {
  Pit p;
  p.bulge = 80;
  auto pts = points_of(p, 8);
  const double a = p.a, B = p.bulge, D = p.depth;
  expect_within(measure(pts, p.depth).v.volume_mm3, kPi * (a * a * D + 4 * a * B * D / kPi + B * B * D / 2),
                0.001);
}

// A vessel's top as wide as a ground (a flat ring 28 mm wide), its outer
// wall at the ring's edge all the way down: the wall below shows the outer
// wall with the inner one behind it, so the ring caps it as a vessel's
// (uncapped: +64 %).
void wide_vessel_top_caps_outer_wall(void **) {
  Pit p;
  p.top_mm = 28;
  p.outer_wall = true;
  auto pts = points_of(p, 9);
  expect_within(measure(pts, p.depth).v.volume_mm3, kPi * 100 * 100 * p.depth, 0.001);
}

void multipath_inside_changes_nothing(void **) {
  Pit p;
  p.multipath = 0.05;
  auto pts = points_of(p, 5);
  expect_within(measure(pts, p.depth).v.volume_mm3, kPi * 100 * 100 * p.depth, 0.001);
}

// A 30 mm band of wall without points: bridged, and the bridge's bounds
// hold the truth; the band counts as unseen.
void removed_band_is_bridged_within_interval(void **) {
  Pit p;
  p.gap_from = 80;
  p.gap_to = 110;
  auto pts = points_of(p, 6);
  const Measured r = measure(pts, p.depth);
  const double truth = kPi * 100 * 100 * p.depth;
  expect_within(r.v.volume_mm3, truth, 0.002);
  assert_true(r.v.lo_mm3 <= truth * 1.001 && r.v.hi_mm3 >= truth * 0.999);
  assert_true(r.unseen_share > 0.05 && r.unseen_share < 0.25);
}

// A neck 20 mm in over 20 mm of height, the 40 mm of wall under it hidden
// all round, and in their place multipath: single points at about the
// neck's radius and inside it, in about half the hidden bins (a long
// scan's). They are not wall: the pit reads as it does without them (taken
// for wall, the hidden band read up to 50 mm inside the wall: -6.7 %).
void fog_under_neck_is_no_wall(void **) {
  Pit p;
  p.neck_mm = 20;
  p.neck_from = 100;
  p.neck_to = 120;
  p.hidden_from = 60;
  auto clear = points_of(p, 10);
  const double without = measure(clear, p.depth).v.volume_mm3;
  p.fog_points = 3000;
  auto fog = points_of(p, 10);
  expect_within(measure(fog, p.depth).v.volume_mm3, without, 0.001);
}

// The MCU profile's grids (pv_config_mcu()) and about its point
// budget: 64 points per 2 mm layer is 32 wall points per mm of height, of
// the 1440 here; its floor store, some 2,500 points.
pv::surface::Params coarse_params(bool coarse) {
  pv::surface::Params prm;
  prm.theta_bins = 36;
  prm.dz_mm = 12;
  prm.cell_mm = 12;
  prm.band_mm = 3;
  prm.integrate_dr_mm = 6;
  prm.coarse_bins = coarse;
  return prm;
}

// The interval's part for the coarse bins, as pv_session_finish adds it
// (core/session/measure_surface.cpp), with the bridge's.
double coarse_interval(const Measured &r, const pv::surface::Model &m) {
  const double bridge = std::max(r.v.hi_mm3 - r.v.volume_mm3, r.v.volume_mm3 - r.v.lo_mm3);
  return bridge + m.sparse_mm3 + m.subbin_mm3;
}

// The coarse profile without and with its coarse-bin handling on the same
// points: with it, within 0.4 % of truth, nearer than without, and the
// truth inside the interval. Returns the model measured with it.
pv::surface::Model expect_coarse_better(const char *what, std::vector<Point> &pts, double depth,
                                        double truth) {
  pv::surface::Model m;
  const Measured off = measure(pts, depth, coarse_params(false));
  const Measured on = measure(pts, depth, coarse_params(true), &m);
  printf("coarse %s: %+.3f %% without, %+.3f %% with, interval +-%.3f %%\n", what,
         100 * (off.v.volume_mm3 / truth - 1), 100 * (on.v.volume_mm3 / truth - 1),
         100 * coarse_interval(on, m) / on.v.volume_mm3);
  expect_within(on.v.volume_mm3, truth, 0.004);
  assert_true(std::fabs(on.v.volume_mm3 - truth) < std::fabs(off.v.volume_mm3 - truth));
  assert_true(std::fabs(on.v.volume_mm3 - truth) <= coarse_interval(on, m));
  return m;
}

// A 10 deg bin of an oval wall spans millimetres of radius and its few
// points lie near its largest: read without the slope along the angle it
// reads outward (here +1.12 %); with the slope borrowed from the
// neighbours, near the truth, and the interval's terms for the sparse bins
// hold the truth.
void coarse_ellipse_borrows_slope(void **) {
  Pit p;
  p.a = 130;
  p.b = 90;
  p.keep_wall = 1.0 / 45;
  p.keep_floor = 1.0 / 12;
  auto pts = points_of(p, 7);
  const double truth = kPi * 130 * 90 * p.depth;
  const pv::surface::Model m = expect_coarse_better("ellipse", pts, p.depth, truth);
  assert_true(m.sparse_mm3 > 0);  // the sparse bins are counted
}

// 12 mm floor cells on a bowl's sides rise more than the flood's 1.5 mm a
// step (set for 2 mm cells): the floor stopped at the bottom and continued
// flat, reading the bowl high (here +0.37 %). Coarse bins keep the flood's
// slope (-0.09 %).
void coarse_bowl_floods_its_sides(void **) {
  Pit p;
  p.bowl_radius = 100;
  p.keep_wall = 1.0 / 45;
  p.keep_floor = 1.0 / 12;
  auto pts = points_of(p, 8);
  const double truth = kPi * 100 * 100 * (p.depth - 100) + 2.0 / 3.0 * kPi * 1e6;
  expect_coarse_better("bowl", pts, p.depth, truth);
}

// The wall behind the wall (surface::shifted_wall): a second pass shifted
// sideways by s lies s |cos| behind the first in each direction, nothing
// behind across the shift; a vessel's outer wall lies a lip's width behind
// all round, seen where the path went outside.
pv::surface::Occupancy behind_wall(const double *mm, const uint32_t *count) {
  pv::surface::Occupancy o{};
  for (uint32_t k = 0; k < pv::surface::kRimSectors; ++k) {
    o.on_wall[k] = 100;
    o.apart[k] = count[k];
    o.apart_mm[k] = mm[k] * count[k];
  }
  return o;
}

void sideways_shift_follows_cos(void **) {
  constexpr uint32_t n = pv::surface::kRimSectors;
  double mm[n];
  uint32_t count[n], behind = 0;
  for (uint32_t k = 0; k < n; ++k) {
    // Shifted 10 mm towards sector 4's centre; within 3 mm nothing counts.
    const double d = 10.0 * std::fabs(std::cos(2.0 * kPi * (double(k) - 4.0) / n));
    mm[k] = d;
    count[k] = d > pv::surface::kApartFromMm ? 70 : 0;
    behind += count[k];
  }
  const pv::surface::ShiftedWall w = pv::surface::shifted_wall(behind_wall(mm, count));
  assert_true(w.fit < 0.05);
  assert_true(std::fabs(w.share - behind / (100.0 * n)) < 1e-12);
}

// Across the shift the other wall comes within the count's cut-off
// (kApartFromMm, or the inside margin in front of a union): the sectors
// there keep the distances the count starts at, a floor under D |cos|.
// Fitted without an offset that floor reads as no shift; with one, the
// shift shows (the check's limits: 0.2 around a vessel, 0.35 elsewhere).
void sideways_shift_over_cut_off_fits_with_offset(void **) {
  constexpr uint32_t n = pv::surface::kRimSectors;
  double mm[n];
  uint32_t count[n];
  for (uint32_t k = 0; k < n; ++k) {
    mm[k] = std::max(10.0 * std::fabs(std::cos(2.0 * kPi * (double(k) - 4.0) / n)), 5.5);
    count[k] = 70;
  }
  const pv::surface::ShiftedWall w = pv::surface::shifted_wall(behind_wall(mm, count));
  assert_true(w.fit > 0.5);
  assert_true(w.offset_fit < 0.2);
  assert_true(w.shift_mm > 4.0 && w.shift_mm < 10.0);
}

void vessel_outer_wall_is_no_shift(void **) {
  constexpr uint32_t n = pv::surface::kRimSectors;
  double mm[n];
  uint32_t count[n];
  // An 8 mm lip; the outer wall seen over two arcs of the path (0-90 and
  // 180-250 deg), the widths within 1 mm.
  for (uint32_t k = 0; k < n; ++k) {
    const bool seen = k < 9 || (k >= 18 && k < 25);
    mm[k] = 8.0 + ((k % 3) - 1.0) * 0.5;
    count[k] = seen ? 40 : 0;
  }
  const pv::surface::ShiftedWall arcs = pv::surface::shifted_wall(behind_wall(mm, count));
  assert_true(arcs.fit > 0.3);
  assert_true(arcs.offset_fit > 0.3);
  // Seen all round, every sector alike: nothing to fit.
  for (uint32_t k = 0; k < n; ++k) {
    mm[k] = 8.0;
    count[k] = 40;
  }
  const pv::surface::ShiftedWall round = pv::surface::shifted_wall(behind_wall(mm, count));
  assert_true(round.fit == 1.0 && round.offset_fit == 1.0);
  // A few strays behind a sector count for nothing.
  for (uint32_t k = 0; k < n; ++k) count[k] = k == 5 ? 4 : 0;
  const pv::surface::ShiftedWall strays = pv::surface::shifted_wall(behind_wall(mm, count));
  assert_true(strays.fit == 1.0 && strays.offset_fit == 1.0);
  assert_true(strays.share < 0.01);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(cylinder_volume_is_exact),
      cmocka_unit_test(frustum_volume_is_exact),
      cmocka_unit_test(ramp_floor_floods_from_its_plane),
      cmocka_unit_test(ramp_floor_without_its_plane_reads_low),
      cmocka_unit_test(ellipse_volume_is_exact),
      cmocka_unit_test(bowl_volume_is_exact),
      cmocka_unit_test(bowl_floor_hole_within_interval),
      cmocka_unit_test(ground_ring_caps_no_bulge),
      cmocka_unit_test(fog_under_neck_is_no_wall),
      cmocka_unit_test(wide_vessel_top_caps_outer_wall),
      cmocka_unit_test(multipath_inside_changes_nothing),
      cmocka_unit_test(removed_band_is_bridged_within_interval),
      cmocka_unit_test(coarse_ellipse_borrows_slope),
      cmocka_unit_test(coarse_bowl_floods_its_sides),
      cmocka_unit_test(sideways_shift_follows_cos),
      cmocka_unit_test(sideways_shift_over_cut_off_fits_with_offset),
      cmocka_unit_test(vessel_outer_wall_is_no_shift),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
