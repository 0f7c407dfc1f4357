// pv::volume against area profiles with closed-form volumes.
#include "pv_cmocka.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "volume/volume.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kMax = 1000;

double g_z[kMax], g_s[kMax], g_scratch[2 * (kMax + 2)];

void assert_rel(double got, double want, double tol) {
  const double rel = std::fabs(got - want) / std::fabs(want);
  if (!(rel <= tol)) print_message("  got %.17g want %.17g rel %.3e > %.1e\n", got, want, rel, tol);
  assert_true(rel <= tol);
}

// Cubic S(z) = c0 + c1 z + c2 z^2 + c3 z^3 and its antiderivative.
struct Cubic {
  double c0, c1, c2, c3;
  double at(double z) const { return c0 + z * (c1 + z * (c2 + z * c3)); }
  double prim(double z) const { return z * (c0 + z * (c1 / 2 + z * (c2 / 3 + z * c3 / 4))); }
};

// Cone frustum: radius r0 + k z, S = pi (r0 + k z)^2.
struct Cone {
  double r0, k;
  double at(double z) const { return kPi * (r0 + k * z) * (r0 + k * z); }
  double prim(double z) const {
    const double r = r0 + k * z;
    return kPi * r * r * r / (3.0 * k);
  }
};

template <class F>
size_t fill_even_grid(const F &f, double z0, double dz, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    g_z[i] = z0 + dz * static_cast<double>(i);
    g_s[i] = f.at(g_z[i]);
  }
  return n;
}

void test_cubic_odd_equal(void **) {
  const Cubic c{3000.0, -25.0, 0.8, -0.004};
  const size_t n = fill_even_grid(c, 2.0, 0.5, 301);
  assert_rel(pv::volume::integrate_mm3(g_z, g_s, n), c.prim(g_z[n - 1]) - c.prim(g_z[0]), 1e-12);
}

void test_cone_odd_and_even(void **) {
  const Cone cone{100.0, 0.3};
  for (size_t n : {201u, 200u, 3u, 2u}) {
    fill_even_grid(cone, 0.5, 0.5, n);
    assert_rel(pv::volume::integrate_mm3(g_z, g_s, n), cone.prim(g_z[n - 1]) - cone.prim(g_z[0]),
               1e-12);
  }
}

// Drops layers so spacings are 0.5, 1.0 and 1.5 mm mixed.
template <class F>
size_t fill_uneven(const F &f, size_t n_grid) {
  size_t m = 0;
  for (size_t i = 0; i < n_grid; ++i) {
    if (i % 7 == 3 || i % 11 == 5 || i % 11 == 6) continue;
    g_z[m] = 1.0 + 0.5 * static_cast<double>(i);
    g_s[m] = f.at(g_z[m]);
    ++m;
  }
  return m;
}

void test_uneven_quadratic(void **) {
  const Cubic q{5000.0, 40.0, -0.9, 0.0};  // general quadratic: odd count needed
  size_t m = fill_uneven(q, 300);
  if (m % 2 == 0) --m;
  assert_true(m % 2 == 1);
  assert_rel(pv::volume::integrate_mm3(g_z, g_s, m), q.prim(g_z[m - 1]) - q.prim(g_z[0]), 1e-12);
  // A cone is quadratic too, and its frustum end is exact: both parities.
  const Cone cone{80.0, 0.4};
  m = fill_uneven(cone, 300);
  for (size_t len : {m, m - 1})
    assert_rel(pv::volume::integrate_mm3(g_z, g_s, len),
               cone.prim(g_z[len - 1]) - cone.prim(g_z[0]), 1e-12);
}

// Layers on the 0.5 mm grid from 1.5 mm to <= H - 1.5 mm.
template <class F>
size_t fill_inside(const F &f, double H) {
  size_t n = 0;
  for (double z = 1.5; z <= H - 1.5 + 1e-12; z = 1.5 + 0.5 * static_cast<double>(n)) {
    g_z[n] = z;
    g_s[n] = f.at(z);
    ++n;
  }
  return n;
}

void test_between_cylinder(void **) {
  const double r = 110.0, H = 150.3;
  const Cubic cyl{kPi * r * r, 0, 0, 0};
  const size_t n = fill_inside(cyl, H);
  pv::volume::Limits lim;
  lim.z_bottom_mm = 0.0;
  lim.z_rim_mm = H;
  double v = 0.0;
  for (size_t len : {n, n - 1}) {  // both parities of the extended sequence
    lim.z_rim_mm = (len == n) ? H : g_z[len - 1] + 1.8;
    assert_true(pv::volume::volume_between_mm3(g_z, g_s, len, lim, g_scratch,
                                               pv::volume::scratch_needed_between(len), &v));
    assert_rel(v, kPi * r * r * lim.z_rim_mm, 1e-12);
  }
}

// Extrapolation error of the LS line through the m layers at distances
// u_j = g + j dz from the limit, for S'' constant (see volume.h, V3).
double end_error_mm2(double s2, double g, double dz, size_t m) {
  double mean = 0.0, var = 0.0;
  for (size_t j = 0; j < m; ++j) mean += g + dz * static_cast<double>(j);
  mean /= static_cast<double>(m);
  for (size_t j = 0; j < m; ++j) {
    const double d = g + dz * static_cast<double>(j) - mean;
    var += d * d;
  }
  var /= static_cast<double>(m);
  return std::fabs(s2 / 2.0 * (var - mean * mean));
}

void test_between_cone_bound(void **) {
  const Cone cone{100.0, 0.3};
  const double H = 150.3, dz = 0.5;
  const size_t n = fill_inside(cone, H);
  pv::volume::Limits lim;
  lim.z_bottom_mm = 0.0;
  lim.z_rim_mm = H;
  const double exact = cone.prim(H) - cone.prim(0.0);
  const double s2 = 2.0 * kPi * cone.k * cone.k;  // S''
  for (size_t len : {n, n - 1}) {
    const double g_bot = g_z[0] - lim.z_bottom_mm;
    const double g_rim = H - g_z[len - 1];
    double v = 0.0;
    assert_true(pv::volume::volume_between_mm3(g_z, g_s, len, lim, g_scratch,
                                               pv::volume::scratch_needed_between(len), &v));
    const double bound =
        std::max((g_bot + dz) / 3.0, g_bot / 2.0) * end_error_mm2(s2, g_bot, dz, 8) +
        std::max((g_rim + dz) / 3.0, g_rim / 2.0) * end_error_mm2(s2, g_rim, dz, 8);
    const double err = std::fabs(v - exact);
    print_message("  cone n=%zu: |err| = %.4f mm3 (rel %.2e), bound %.4f mm3\n", len, err,
                  err / exact, bound);
    assert_true(err <= bound * (1.0 + 1e-6) + 1e-12 * exact);
    // Without the limits, the end slabs would be missing: orders larger.
    const double naive = std::fabs(pv::volume::integrate_mm3(g_z, g_s, len) - exact);
    assert_true(naive > 100.0 * bound);
  }
}

void test_invalid(void **) {
  const double z[] = {0.0, 1.0, 1.0, 2.0};
  const double s[] = {1.0, 1.0, 1.0, 1.0};
  assert_true(pv::volume::integrate_mm3(z, s, 4) == 0.0);  // not strictly increasing
  assert_true(pv::volume::integrate_mm3(z, s, 1) == 0.0);
  assert_true(pv::volume::integrate_mm3(nullptr, s, 2) == 0.0);
  const double z2[] = {1.0, 2.0, 3.0};
  pv::volume::Limits lim;
  lim.z_bottom_mm = 1.5;  // layer below the bottom limit
  lim.z_rim_mm = 4.0;
  double v = 0.0, scratch[10];
  assert_false(pv::volume::volume_between_mm3(z2, s, 3, lim, scratch, 10, &v));
  lim.z_bottom_mm = 0.0;
  assert_false(pv::volume::volume_between_mm3(z2, s, 3, lim, scratch, 9, &v));  // scratch short
  assert_true(pv::volume::volume_between_mm3(z2, s, 3, lim, scratch, 10, &v));
  assert_rel(v, 4.0, 1e-15);
  // Limits on the outermost layers: no extrapolated point, plain integral.
  lim.z_bottom_mm = 1.0;
  lim.z_rim_mm = 3.0;
  assert_true(pv::volume::volume_between_mm3(z2, s, 3, lim, scratch, 10, &v));
  assert_rel(v, 2.0, 1e-15);
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cubic_odd_equal),  cmocka_unit_test(test_cone_odd_and_even),
      cmocka_unit_test(test_uneven_quadratic), cmocka_unit_test(test_between_cylinder),
      cmocka_unit_test(test_between_cone_bound), cmocka_unit_test(test_invalid),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
