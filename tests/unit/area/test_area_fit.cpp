// pv::area::fit_area against closed contours with exact analytic areas,
// sampled with Gaussian noise from a fixed-seed generator.

#include <cmath>
#include <cstring>

#include "area/area_fit.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::kPi;
using pv::test::Rng;
constexpr size_t kMaxN = 4000;


// Contour r(theta) = r0 + a sin(k theta) around (cx, cy), stretched to an
// ellipse by (sx, sy); theta uniform at random, noise sigma on x and y.
struct Shape {
  double cx, cy, sx, sy, r0, a;
  int k;
};

size_t sample(const Shape &s, size_t n, double sigma_mm, uint64_t seed, pv::XY *pts) {
  Rng rng{seed};
  for (size_t i = 0; i < n; ++i) {
    const double th = 2.0 * kPi * rng.uniform();
    const double r = s.r0 + s.a * std::sin(s.k * th);
    pts[i].x_mm = s.cx + s.sx * r * std::cos(th) + sigma_mm * rng.gauss();
    pts[i].y_mm = s.cy + s.sy * r * std::sin(th) + sigma_mm * rng.gauss();
  }
  return n;
}

// Exact area of the shape: (sx sy) * (pi r0^2 + pi a^2 / 2) for k >= 1.
double exact_area(const Shape &s) {
  return s.sx * s.sy * (kPi * s.r0 * s.r0 + (s.a != 0.0 ? kPi * s.a * s.a / 2.0 : 0.0));
}

pv::XY g_pts[kMaxN];
pv::XY g_scratch[2 * kMaxN];

double fitted_area(size_t n, const pv::area::Params &p = pv::area::Params{}) {
  pv::area::Result res;
  assert_true(pv::area::fit_area(g_pts, n, p, g_scratch, 2 * kMaxN, &res));
  return res.area_mm2;
}

double rel_err(const Shape &s, size_t n, uint64_t seed, const pv::area::Params &p) {
  sample(s, n, 0.1, seed, g_pts);
  const double exact = exact_area(s);
  const double got = fitted_area(n, p);
  const double rel = (got - exact) / exact;
  print_message("  n=%zu seed=%llu area=%.4f exact=%.4f rel=%+.3e\n", n,
                static_cast<unsigned long long>(seed), got, exact, rel);
  return rel;
}

// Returns the largest |relative error| seen over n and seeds.
double check_shape(const Shape &s, const pv::area::Params &p = pv::area::Params{}) {
  const size_t ns[] = {1000, 2000, 3000};
  double worst = 0.0;
  for (size_t n : ns)
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      const double e = std::fabs(rel_err(s, n, seed, p));
      assert_true(e < 1e-3);
      worst = e > worst ? e : worst;
    }
  print_message("  worst |rel| = %.3e\n", worst);
  return worst;
}

void test_circle(void **) { check_shape(Shape{0, 0, 1, 1, 110, 0, 0}); }

void test_ellipse(void **) {
  // Semi-axes 120 (x) and 90 (y): r0 = 1, stretched.
  check_shape(Shape{0, 0, 120, 90, 1, 0, 0});
}

void test_bumpy(void **) {
  const Shape s{0, 0, 1, 1, 110, 4, 5};
  check_shape(s);
  // The chord split (D8) removes the end-fold bias of the y_mid split.
  pv::area::Params chord;
  chord.split_through_extremes = true;
  print_message("  chord split:\n");
  assert_true(check_shape(s, chord) < 2e-4);
}

void test_offset_centre(void **) {
  const Shape centred{0, 0, 1, 1, 110, 0, 0};
  const Shape offset{500, -300, 1, 1, 110, 0, 0};
  sample(centred, 2000, 0.1, 7, g_pts);
  const double a0 = fitted_area(2000);
  sample(offset, 2000, 0.1, 7, g_pts);
  const double a1 = fitted_area(2000);
  print_message("  centred %.6f offset %.6f\n", a0, a1);
  // Same noise draws: only the translation differs, so the fit must agree
  // far tighter than the accuracy bound (conditioning, D5).
  assert_true(std::fabs(a1 - a0) / a0 < 1e-9);
  assert_true(std::fabs(a1 - exact_area(offset)) / exact_area(offset) < 1e-3);
}

void test_order_independent(void **) {
  const Shape s{0, 0, 1, 1, 110, 4, 5};
  sample(s, 1500, 0.1, 11, g_pts);
  const double a0 = fitted_area(1500);
  Rng rng{99};
  for (size_t i = 1500 - 1; i > 0; --i) {  // Fisher-Yates
    const size_t j = static_cast<size_t>(rng.next() % (i + 1));
    const pv::XY t = g_pts[i];
    g_pts[i] = g_pts[j];
    g_pts[j] = t;
  }
  const double a1 = fitted_area(1500);
  assert_memory_equal(&a0, &a1, sizeof(double));
}

void test_too_few_points(void **) {
  sample(Shape{0, 0, 1, 1, 110, 0, 0}, 5, 0.1, 3, g_pts);
  pv::area::Result res;
  assert_false(pv::area::fit_area(g_pts, 5, pv::area::Params{}, g_scratch, 2 * kMaxN, &res));
  assert_false(pv::area::fit_area(g_pts, 0, pv::area::Params{}, g_scratch, 2 * kMaxN, &res));
}

void test_degenerate_and_scratch(void **) {
  pv::area::Result res;
  // All points on one vertical line: zero x extent.
  for (size_t i = 0; i < 50; ++i) g_pts[i] = pv::XY{3.0, static_cast<double>(i)};
  assert_false(pv::area::fit_area(g_pts, 50, pv::area::Params{}, g_scratch, 2 * kMaxN, &res));
  // Scratch one element short.
  sample(Shape{0, 0, 1, 1, 110, 0, 0}, 100, 0.1, 3, g_pts);
  assert_int_equal(pv::area::scratch_needed(100), 200);
  assert_false(pv::area::fit_area(g_pts, 100, pv::area::Params{}, g_scratch, 199, &res));
  assert_true(pv::area::fit_area(g_pts, 100, pv::area::Params{}, g_scratch, 200, &res));
  // NaN input.
  g_pts[10].x_mm = NAN;
  assert_false(pv::area::fit_area(g_pts, 100, pv::area::Params{}, g_scratch, 200, &res));
}

void test_sparse_layer(void **) {
  // 300 points: fewer pieces (D2); accuracy degrades gracefully (~0.4 % worst).
  const Shape s{0, 0, 1, 1, 110, 0, 0};
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    sample(s, 300, 0.1, seed, g_pts);
    pv::area::Result res;
    assert_true(pv::area::fit_area(g_pts, 300, pv::area::Params{}, g_scratch, 2 * kMaxN, &res));
    assert_true(res.pieces_upper < 16 && res.pieces_upper >= 1);
    const double rel = (res.area_mm2 - exact_area(s)) / exact_area(s);
    print_message("  300 points: pieces %u/%u rel=%+.3e\n", res.pieces_upper, res.pieces_lower, rel);
    assert_true(std::fabs(rel) < 5e-3);
  }
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_circle),          cmocka_unit_test(test_ellipse),
      cmocka_unit_test(test_bumpy),           cmocka_unit_test(test_offset_centre),
      cmocka_unit_test(test_order_independent), cmocka_unit_test(test_too_few_points),
      cmocka_unit_test(test_degenerate_and_scratch), cmocka_unit_test(test_sparse_layer),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
