// pv::area::polar_area (method "polar") against closed contours with exact
// areas, with 0.1 mm noise, interior strays, and an unseen arc.
#include <cmath>
#include <vector>

#include "area/polar_area.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::kPi;
using pv::test::Rng;

struct Contour {
  double a, b;      // ellipse semi-axes (a == b: circle)
  double bump, k;   // r += bump * sin(k theta) on the circle
  double cx, cy;
};

// n points on the contour, theta uniform except a skipped arc [gap_from, gap_to).
std::vector<pv::XY> sample(const Contour &c, size_t n, double noise, uint64_t seed,
                           double gap_from = 0, double gap_to = 0) {
  Rng rng{seed};
  std::vector<pv::XY> v;
  while (v.size() < n) {
    const double t = 2 * kPi * rng.uniform();
    if (t >= gap_from && t < gap_to) continue;
    double r = c.a * c.b / std::hypot(c.b * std::cos(t), c.a * std::sin(t));
    r += c.bump * std::sin(c.k * t) + noise * rng.gauss();
    v.push_back(pv::XY{c.cx + r * std::cos(t), c.cy + r * std::sin(t)});
  }
  return v;
}

double area_of(const std::vector<pv::XY> &v, pv::area::PolarResult *res = nullptr) {
  std::vector<double> scratch(pv::area::polar_scratch_needed(v.size()));
  pv::area::PolarResult r;
  if (!pv::area::polar_area(v.data(), v.size(), pv::area::PolarParams{}, scratch.data(),
                            scratch.size(), &r))
    return -1;
  if (res) *res = r;
  return r.area_mm2;
}

void circle_ellipse_and_bumpy_within_0_1_percent(void **) {
  const Contour cs[] = {{110, 110, 0, 0, 0, 0}, {130, 90, 0, 0, 500, -300}, {110, 110, 4, 5, 0, 0}};
  for (const Contour &c : cs) {
    // Exact: pi a b for the ellipse; pi r0^2 + pi bump^2 / 2 for the bumpy
    // circle (the sin term integrates to zero over a full turn).
    const double exact = kPi * c.a * c.b + kPi * c.bump * c.bump / 2;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      const double a = area_of(sample(c, 1500, 0.1, seed));
      assert_true(std::fabs(a - exact) / exact < 1e-3);
    }
  }
}

void sparse_layers_still_fit(void **) {
  const Contour c{110, 110, 0, 0, 0, 0};
  const double exact = kPi * 110 * 110;
  const double a = area_of(sample(c, 60, 0.1, 9));
  assert_true(std::fabs(a - exact) / exact < 2e-3);
}

void interior_strays_are_trimmed(void **) {
  const Contour c{110, 110, 0, 0, 0, 0};
  std::vector<pv::XY> v = sample(c, 1000, 0.1, 4);
  Rng rng{5};
  for (int i = 0; i < 50; ++i) {  // 5 % floating 5-40 mm in front of the wall
    const double t = 2 * kPi * rng.uniform(), r = 110 - 5 - 35 * rng.uniform();
    v.push_back(pv::XY{r * std::cos(t), r * std::sin(t)});
  }
  pv::area::PolarResult res;
  const double a = area_of(v, &res);
  assert_true(std::fabs(a - kPi * 110 * 110) / (kPi * 110 * 110) < 1e-3);
  assert_true(res.points_used <= 1000 + 5);
}

void an_unseen_arc_is_bridged_or_refused(void **) {
  const Contour c{110, 110, 0, 0, 0, 0};
  // 30 degrees unseen: bridged smoothly (harmonics capped by the gap).
  const double a = area_of(sample(c, 1000, 0.1, 6, 1.0, 1.0 + kPi / 6));
  assert_true(std::fabs(a - kPi * 110 * 110) / (kPi * 110 * 110) < 2e-3);
  // Half the contour unseen: refused.
  assert_true(area_of(sample(c, 1000, 0.1, 7, 0.0, kPi)) < 0);
}

void too_few_points_refused(void **) {
  const Contour c{110, 110, 0, 0, 0, 0};
  assert_true(area_of(sample(c, 10, 0.1, 8)) < 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(circle_ellipse_and_bumpy_within_0_1_percent),
      cmocka_unit_test(sparse_layers_still_fit),
      cmocka_unit_test(interior_strays_are_trimmed),
      cmocka_unit_test(an_unseen_arc_is_bridged_or_refused),
      cmocka_unit_test(too_few_points_refused),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
