// pv_session_wall_grid(): the surface model's wall grid against analytic
// truth (a cylinder's radius, a frustum's sloping radius, a wall sector cut
// out of the scan) and against the result it was measured with.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

constexpr size_t kPoints = 120000;

struct Grid {
  pv_wall_grid_t g{};
  std::vector<float> radius;
  std::vector<uint8_t> state;
  double z_of(uint32_t k) const { return g.z0_mm + (k + 0.5) * g.dz_mm; }
  double theta_deg(uint32_t t) const { return (t + 0.5) * 360.0 / g.theta_bins; }
  size_t at(uint32_t t, uint32_t k) const { return size_t(k) * g.theta_bins + t; }
};

// Measures pts with method surface; the grid after finish.
Grid measure(const std::vector<pv_point_t> &pts, pv_result_t *r) {
  TestSession t;
  assert_int_equal(t.cfg.method, PV_METHOD_SURFACE);
  assert_int_equal(t.push_all(pts, 8192), PV_OK);
  assert_int_equal(pv_session_finish(t.s, r), PV_OK);
  Grid out;
  assert_int_equal(pv_session_wall_grid(t.s, &out.g, nullptr, nullptr, 0), PV_OK);
  const size_t n = size_t(out.g.theta_bins) * out.g.z_bins;
  assert_true(n > 0);
  out.radius.resize(n);
  out.state.resize(n);
  assert_int_equal(pv_session_wall_grid(t.s, &out.g, out.radius.data(), out.state.data(), n), PV_OK);
  // Asked again: the same bits (deterministic rebuild of the same model).
  Grid again;
  again.radius.resize(n);
  again.state.resize(n);
  assert_int_equal(pv_session_wall_grid(t.s, &again.g, again.radius.data(), again.state.data(), n),
                   PV_OK);
  assert_memory_equal(&out.g, &again.g, sizeof out.g);
  assert_memory_equal(out.radius.data(), again.radius.data(), n * sizeof(float));
  assert_memory_equal(out.state.data(), again.state.data(), n);
  return out;
}

// Wall radius rows within [lo, hi] mm against truth(z): the median and the
// 99th percentile of the error over the seen bins.
void check_radius(const Grid &g, double lo, double hi, double (*truth)(double), double med_tol,
                  double max_tol) {
  std::vector<double> err;
  for (uint32_t k = 0; k < g.g.z_bins; ++k) {
    const double z = g.z_of(k);
    if (z < lo || z > hi) continue;
    for (uint32_t t = 0; t < g.g.theta_bins; ++t) {
      if (g.state[g.at(t, k)] != PV_WALL_SEEN) continue;
      err.push_back(std::fabs(g.radius[g.at(t, k)] - truth(z)));
    }
  }
  assert_true(err.size() > 100);
  std::sort(err.begin(), err.end());
  // The 99th percentile: a few sparse bins hold a stray the model keeps
  // (its own outlier test is tuned on the volume, not here).
  const double med = err[err.size() / 2], worst = err[err.size() * 99 / 100];
  if (med > med_tol || worst > max_tol) {
    print_error("radius error: median %.3f mm (bound %.3f), 99th percentile %.3f mm (bound %.3f)\n",
                med, med_tol, worst, max_tol);
  }
  assert_true(med <= med_tol);
  assert_true(worst <= max_tol);
}

double cylinder_radius(double) { return 110.0; }
double frustum_radius(double z) { return 100.0 + 30.0 * z / 290.0; }

void cylinder(void **) {
  pv::synth::PitSpec spec;  // 110 mm x 290 mm, tilted 12 deg
  pv_result_t r;
  const Grid g = measure(scan_points(spec, kPoints), &r);
  assert_true(g.g.rim_mm == r.depth_mm);
  assert_int_equal(g.g.theta_bins, 180);
  assert_true(std::fabs(g.g.dz_mm - 2.0) < 1e-12);
  // Levelled: the axis stands up (lean well under a degree).
  assert_true(std::hypot(g.g.axis_dx, g.g.axis_dy) < 0.01);
  check_radius(g, 10.0, 280.0, cylinder_radius, 0.3, 2.0);
}

void frustum(void **) {
  pv::synth::PitSpec spec;
  spec.radius_bottom_mm = 100.0;
  spec.radius_top_mm = 130.0;
  pv_result_t r;
  const Grid g = measure(scan_points(spec, kPoints), &r);
  check_radius(g, 10.0, 280.0, frustum_radius, 0.5, 2.5);
}

// The coverage the result reports is the share of known bins per band
// (seen, floor, short bridge): recomputed from the grid's states, equal.
void expect_coverage_of_result(const Grid &g, const pv_result_t &r) {
  assert_int_equal(r.coverage_bands, PV_COVERAGE_BANDS);
  for (uint32_t b = 0; b < PV_COVERAGE_BANDS; ++b) {
    uint32_t seen = 0, total = 0;
    for (uint32_t k = 0; k < g.g.z_bins; ++k) {
      const double zc = g.g.z0_mm + (k + 0.5) * (g.g.rim_mm - g.g.z0_mm) / g.g.z_bins;
      if (zc < 0 || int(zc / g.g.rim_mm * PV_COVERAGE_BANDS) != int(b)) continue;
      for (uint32_t t = 0; t < g.g.theta_bins; ++t) {
        const uint8_t s = g.state[g.at(t, k)];
        ++total;
        seen += s == PV_WALL_SEEN || s == PV_WALL_FLOOR || s == PV_WALL_SHORT_BRIDGE;
      }
    }
    const float share = total ? float(seen) / float(total) : 0.0f;
    if (!(std::fabs(share - r.coverage[b]) < 1e-6f)) {
      print_error("band %u: grid %.6f, result %.6f\n", b, double(share), double(r.coverage[b]));
      fail();
    }
  }
}
void coverage_matches_result(void **) {
  pv::synth::PitSpec spec;
  pv_result_t r;
  const Grid g = measure(scan_points(spec, kPoints), &r);
  expect_coverage_of_result(g, r);
}

// The circle through a row's seen bins about the grid's axis (least
// squares r = R + a cos + b sin: an axis a few mm off the pit's centre
// moves each bin's radius by up to that much, not the circle's), the
// median of R over the rows within [lo, hi] mm.
double median_row_radius(const Grid &g, double lo, double hi) {
  std::vector<double> rs;
  for (uint32_t k = 0; k < g.g.z_bins; ++k) {
    const double z = g.z_of(k);
    if (z < lo || z > hi) continue;
    double s[3][3] = {}, v[3] = {};
    uint32_t n = 0;
    for (uint32_t t = 0; t < g.g.theta_bins; ++t) {
      if (g.state[g.at(t, k)] != PV_WALL_SEEN) continue;
      const double a = g.theta_deg(t) * M_PI / 180.0, f[3] = {1.0, std::cos(a), std::sin(a)};
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) s[i][j] += f[i] * f[j];
        v[i] += f[i] * g.radius[g.at(t, k)];
      }
      ++n;
    }
    if (n < g.g.theta_bins / 2) continue;
    // Cramer's rule for R (the first unknown).
    const auto det = [](const double m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    double m0[3][3];
    std::memcpy(m0, s, sizeof s);
    for (int i = 0; i < 3; ++i) m0[i][0] = v[i];
    rs.push_back(det(m0) / det(s));
  }
  assert_true(rs.size() > 20);
  std::sort(rs.begin(), rs.end());
  return rs[rs.size() / 2];
}

// A pit wider than surface_max_radius_mm (320 mm) is measured on grids
// scaled to it (floor cells and integration rings): the grid given is the
// one the volume was integrated over. Built on the configured grids, whose
// floor map stops at 320 mm, it had no floor bins at the wall's foot where
// the measured model has them (the floor meets the wall all round).
void wide_pit_grid_is_the_measured_one(void **) {
  pv::synth::PitSpec spec;
  spec.radius_bottom_mm = spec.radius_top_mm = 450.0;
  spec.depth_mm = 200.0;
  spec.tilt_deg = 3.0;
  pv_result_t r;
  const Grid g = measure(scan_points(spec, 3 * kPoints), &r);
  expect_coverage_of_result(g, r);
  uint32_t floor_bins = 0;
  for (uint8_t st : g.state) floor_bins += st == PV_WALL_FLOOR;
  if (floor_bins < g.g.theta_bins / 4) {
    print_error("%u floor bins at the wall's foot (%u theta bins)\n", floor_bins, g.g.theta_bins);
    fail();
  }
  const double radius = median_row_radius(g, 10.0, 190.0);
  if (!(std::fabs(radius - 450.0) <= 0.5)) {
    print_error("wall circle radius %.3f mm against 450\n", radius);
    fail();
  }
}

// A sector of wall (0..90 deg, 100..160 mm) cut out of an untilted scan:
// the grid marks it unseen and the wall around it seen.
void unseen_sector(void **) {
  pv::synth::PitSpec spec;
  spec.tilt_deg = 0.0;
  spec.yaw_deg = 0.0;
  pv::synth::PitScan scan(spec);
  std::vector<pv_point_t> pts;
  while (pts.size() < kPoints) {
    const pv_point_t p = scan.next();
    const double x = p.x_mm - spec.offset_mm[0], y = p.y_mm - spec.offset_mm[1];
    const double z = p.z_mm - spec.offset_mm[2];
    double a = std::atan2(y, x) * 180.0 / M_PI;
    if (a < 0) a += 360.0;
    if (a < 90.0 && z > 100.0 && z < 160.0) continue;
    pts.push_back(p);
  }
  pv_result_t r;
  const Grid g = measure(pts, &r);
  assert_true(r.unseen_share > 0.0);
  assert_true(r.warnings & PV_WARN_BRIDGED);
  uint32_t inside = 0, inside_unseen = 0, outside = 0, outside_seen = 0;
  for (uint32_t k = 0; k < g.g.z_bins; ++k) {
    const double z = g.z_of(k);
    if (z < 115.0 || z > 145.0) continue;
    for (uint32_t t = 0; t < g.g.theta_bins; ++t) {
      const double a = g.theta_deg(t);
      const uint8_t s = g.state[g.at(t, k)];
      if (a > 20.0 && a < 70.0) {
        ++inside;
        inside_unseen += s == PV_WALL_UNSEEN;
      } else if (a > 120.0 && a < 330.0) {
        ++outside;
        outside_seen += s == PV_WALL_SEEN || s == PV_WALL_SHORT_BRIDGE;  // sparse: 120k points
      }
    }
  }
  if (inside_unseen != inside || outside_seen * 100 < outside * 95) {
    print_error("cut sector: %u of %u bins unseen; around it %u of %u seen\n", inside_unseen, inside,
                outside_seen, outside);
  }
  assert_true(inside > 0 && outside > 0);
  assert_int_equal(inside_unseen, inside);
  assert_true(outside_seen * 100 >= outside * 95);
  // Bridged across the cut, the radius stays the cylinder's.
  for (uint32_t k = 0; k < g.g.z_bins; ++k) {
    if (g.z_of(k) < 115.0 || g.z_of(k) > 145.0) continue;
    for (uint32_t t = 0; t < g.g.theta_bins; ++t) {
      if (g.state[g.at(t, k)] == PV_WALL_UNSEEN) assert_true(std::fabs(g.radius[g.at(t, k)] - 110.0) < 2.0);
    }
  }
}

void errors(void **) {
  pv_wall_grid_t g;
  assert_int_equal(pv_session_wall_grid(nullptr, &g, nullptr, nullptr, 0), PV_ERR_INVALID_ARGUMENT);
  {
    TestSession t;
    assert_int_equal(pv_session_wall_grid(t.s, nullptr, nullptr, nullptr, 0), PV_ERR_INVALID_ARGUMENT);
    assert_int_equal(pv_session_wall_grid(t.s, &g, nullptr, nullptr, 0), PV_ERR_TOO_FEW_POINTS);
    // Too small a buffer: refused, the grid's size filled.
    pv::synth::PitSpec spec;
    assert_int_equal(t.push_all(scan_points(spec, kPoints), 8192), PV_OK);
    pv_result_t r;
    assert_int_equal(pv_session_finish(t.s, &r), PV_OK);
    std::vector<float> small(10);
    assert_int_equal(pv_session_wall_grid(t.s, &g, small.data(), nullptr, small.size()),
                     PV_ERR_INVALID_ARGUMENT);
    assert_true(g.theta_bins * g.z_bins > small.size());
  }
  // The per-layer methods have no wall grid.
  TestSession paper([](pv_config_t *c) { c->method = PV_METHOD_PAPER; });
  pv::synth::PitSpec spec;
  assert_int_equal(paper.push_all(scan_points(spec, kPoints), 8192), PV_OK);
  pv_result_t r;
  assert_int_equal(pv_session_finish(paper.s, &r), PV_OK);
  assert_int_equal(pv_session_wall_grid(paper.s, &g, nullptr, nullptr, 0), PV_ERR_WRONG_STATE);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(cylinder),
      cmocka_unit_test(frustum),
      cmocka_unit_test(coverage_matches_result),
      cmocka_unit_test(wide_pit_grid_is_the_measured_one),
      cmocka_unit_test(unseen_sector),
      cmocka_unit_test(errors),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
