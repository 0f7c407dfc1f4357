// The core's libm-free angles (common/angle.h, surface/angle_bins.h) against
// libm's atan2, sin and cos (independent truth): pv::sin_cos,
// pv::surface::AngleBins (theta bins, bin centres, angle from a centre),
// pv::angle_2pi, pv::angle_pi (against atan2) and pv::angle_of_cos
// (against acos).
#include <cmath>
#include <cstdint>
#include <initializer_list>

#include "common/angle.h"
#include "surface/angle_bins.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::surface::AngleBins;
using pv::test::kPi;
using pv::test::Rng;

double libm_angle(double y, double x) {
  const double a = std::atan2(y, x);
  return a < 0 ? a + 2 * kPi : a;
}

// A random point: uniform in a square, with some on the axes and some tiny.
void random_point(Rng &rng, uint32_t i, double *x, double *y) {
  *x = (rng.uniform() - 0.5) * 800.0;
  *y = (rng.uniform() - 0.5) * 800.0;
  if (i % 13 == 0) *y = 0.0;
  if (i % 17 == 0) *x = 0.0;
  if (i % 19 == 0) *x *= 1e-9;
}

void sin_cos_match_libm(void **) {
  double worst = 0;
  for (int i = 0; i <= 100000; ++i) {
    const double a = 2 * kPi * i / 100000.0;
    double s, c;
    pv::sin_cos(a, &s, &c);
    worst = std::fmax(worst, std::fmax(std::fabs(s - std::sin(a)), std::fabs(c - std::cos(a))));
  }
  assert_true(worst <= 4.5e-16);  // about 2 ulp of 1
}

// Each point's bin is floor(angle * n / 2 pi), except within rounding of
// an edge (where either neighbour is right).
void bins_match_atan2(void **) {
  static AngleBins bins[3];
  static double tables[3][2048];  // bytes_for(360) and less
  const uint32_t counts[3] = {180, 36, 360};
  for (int k = 0; k < 3; ++k) {
    assert_true(AngleBins::bytes_for(counts[k]) <= sizeof tables[k]);
    bins[k].init(counts[k], tables[k]);
    const uint32_t n = counts[k];
    Rng rng{uint64_t(7 + k)};
    uint32_t near_edge = 0;
    for (uint32_t i = 0; i < 400000; ++i) {
      double x, y;
      random_point(rng, i, &x, &y);
      if (x == 0 && y == 0) continue;
      const double u = libm_angle(y, x) * (n / (2 * kPi));
      uint32_t want = uint32_t(u);
      if (want >= n) want = n - 1;
      const uint32_t got = bins[k].bin(x, y);
      assert_true(got < n);
      if (got == want) continue;
      const double edge = std::round(u);
      assert_true(std::fabs(u - edge) < 1e-9);  // on an edge: either side
      ++near_edge;
    }
    assert_true(near_edge < 10);
  }
}

// The angle from the bin centre agrees with atan2 minus the centre angle.
void from_centre_matches_atan2(void **) {
  static AngleBins bins;
  static double tables[2048];
  bins.init(180, tables);
  Rng rng{11};
  double worst = 0;
  for (uint32_t i = 0; i < 200000; ++i) {
    double x, y;
    random_point(rng, i, &x, &y);
    if (std::hypot(x, y) < 1e-3) continue;
    const uint32_t t = bins.bin(x, y);
    const double want = libm_angle(y, x) - (t + 0.5) * (2 * kPi / 180);
    const double got = bins.from_centre(t, x, y);
    worst = std::fmax(worst, std::fabs(got - want));
    assert_true(std::fabs(got) <= kPi / 180 + 1e-12);
    // (the centre angle itself rounds differently: a few ulp)
    assert_true(std::fabs(bins.centre_cos(t) - std::cos((t + 0.5) * 2 * kPi / 180)) < 2e-15);
  }
  assert_true(worst < 5e-15);
}

void angle_2pi_matches_atan2(void **) {
  Rng rng{5};
  double worst = 0;
  for (uint32_t i = 0; i < 400000; ++i) {
    double x, y;
    random_point(rng, i, &x, &y);
    const double got = pv::angle_2pi(y, x);
    assert_true(got >= 0 && got <= 2 * kPi);
    worst = std::fmax(worst, std::fabs(got - libm_angle(y, x)));
  }
  assert_true(worst <= 2 * 8.9e-16);  // 2 ulp of 2 pi
  assert_true(pv::angle_2pi(0.0, 0.0) == 0.0);
  assert_true(pv::angle_2pi(0.0, -1.0) == kPi);
  assert_true(std::fabs(pv::angle_2pi(-1.0, 0.0) - 1.5 * kPi) < 1e-15);
}

// The crescent window's angle (clustering) in atan2's range (-pi, pi].
void angle_pi_matches_atan2(void **) {
  Rng rng{6};
  double worst = 0;
  for (uint32_t i = 0; i < 400000; ++i) {
    double x, y;
    random_point(rng, i, &x, &y);
    const double got = pv::angle_pi(y, x);
    assert_true(got > -kPi && got <= kPi);
    worst = std::fmax(worst, std::fabs(got - std::atan2(y, x)));
  }
  assert_true(worst <= 2 * 8.9e-16);  // 2 ulp of 2 pi (the 2 pi taken off)
  assert_true(pv::angle_pi(0.0, 0.0) == 0.0);
  assert_true(pv::angle_pi(0.0, -1.0) == kPi);
  assert_true(pv::angle_pi(1.0, 0.0) == 0.5 * kPi);
  assert_true(std::fabs(pv::angle_pi(-1.0, 0.0) + 0.5 * kPi) < 1e-15);
  assert_true(std::fabs(pv::angle_pi(-1.0, -1.0) + 0.75 * kPi) < 1e-15);
}

// acos without libm: against std::acos over [-1, 1], densest near +-1
// where the angle is small (the levelling's convergence test compares tilts
// of 1e-4 deg) and relative accuracy is what matters.
void angle_of_cos_matches_acos(void **) {
  double worst_abs = 0, worst_rel = 0;
  for (int i = 0; i <= 200000; ++i) {
    const double u = -1.0 + 2.0 * i / 200000.0;
    for (double c : {u, 1.0 - std::ldexp(1.0, -(i % 52) - 1), -1.0 + std::ldexp(1.0, -(i % 52) - 1)}) {
      const double got = pv::angle_of_cos(c), want = std::acos(c);
      assert_true(got >= 0 && got <= kPi);
      worst_abs = std::fmax(worst_abs, std::fabs(got - want));
      if (want > 0) worst_rel = std::fmax(worst_rel, std::fabs(got - want) / want);
    }
  }
  assert_true(worst_abs <= 2 * 4.5e-16);  // 2 ulp of pi
  assert_true(worst_rel <= 1e-15);        // small angles too
  assert_true(pv::angle_of_cos(1.0) == 0.0);
  assert_true(pv::angle_of_cos(-1.0) == kPi);
  assert_true(pv::angle_of_cos(1.5) == 0.0);  // clamped, as the callers did
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sin_cos_match_libm),
      cmocka_unit_test(bins_match_atan2),
      cmocka_unit_test(from_centre_matches_atan2),
      cmocka_unit_test(angle_2pi_matches_atan2),
      cmocka_unit_test(angle_pi_matches_atan2),
      cmocka_unit_test(angle_of_cos_matches_acos),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
