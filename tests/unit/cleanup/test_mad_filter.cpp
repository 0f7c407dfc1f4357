// pv::cleanup::mad_filter on synthetic area sequences with known outliers.

#include <cmath>
#include <cstring>

#include "cleanup/mad_filter.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::kPi;
using pv::test::Rng;
constexpr size_t kN = 300;  // layers 0.5 .. 150 mm on the 0.5 mm grid


enum class Profile { kCone, kLinearBottom, kQuadraticBottom, kConstant };

// Area profiles over height z above the bottom (mm).
double area_at(Profile pr, double z) {
  const double s_top = kPi * 110.0 * 110.0;
  switch (pr) {
    case Profile::kCone:  // radius 60 mm at the bottom to ~110 mm at the rim
      return kPi * (60.0 + 0.33 * z) * (60.0 + 0.33 * z);
    case Profile::kLinearBottom:  // straight wall, then linear to 20 % in 30 mm
      return z >= 30.0 ? s_top : s_top * (0.2 + 0.8 * z / 30.0);
    case Profile::kQuadraticBottom:  // smooth rounding into the bottom
      return z >= 30.0 ? s_top : s_top * (1.0 - 0.8 * (1.0 - z / 30.0) * (1.0 - z / 30.0));
    case Profile::kConstant:
      return s_top;
  }
  return 0.0;
}

double g_z[kN], g_s[kN], g_scratch[3 * kN];
uint8_t g_keep[kN];

void fill(Profile pr, double rel_noise, uint64_t seed) {
  Rng rng{seed};
  for (size_t i = 0; i < kN; ++i) {
    g_z[i] = 0.5 * static_cast<double>(i + 1);
    g_s[i] = area_at(pr, g_z[i]) * (1.0 + rel_noise * rng.gauss());
  }
}

size_t run(const pv::cleanup::Params &p = pv::cleanup::Params{}) {
  return pv::cleanup::mad_filter(g_z, g_s, kN, p, g_keep, g_scratch, 3 * kN);
}

void test_spikes_removed(void **) {
  // Five single-layer +-3 % spikes, two of them in the steep late segment.
  const size_t spikes[] = {12, 40, 120, 200, 290};
  size_t lost_good = 0, good = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    fill(Profile::kCone, 2e-4, seed);
    for (size_t k = 0; k < 5; ++k) g_s[spikes[k]] *= (k % 2 == 0) ? 1.03 : 0.97;
    run();
    for (size_t k = 0; k < 5; ++k) assert_int_equal(g_keep[spikes[k]], 0);
    for (size_t i = 0; i < kN; ++i) {
      bool spike = false;
      for (size_t k = 0; k < 5; ++k) spike = spike || (i == spikes[k]);
      if (spike) continue;
      ++good;
      lost_good += g_keep[i] ? 0 : 1;
    }
  }
  print_message("  good layers lost: %zu of %zu (%.2f %%)\n", lost_good, good,
                100.0 * static_cast<double>(lost_good) / static_cast<double>(good));
  assert_true(static_cast<double>(lost_good) <= 0.01 * static_cast<double>(good));
}

void check_trend_kept(Profile pr, const char *name) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    fill(pr, 2e-4, seed);
    const size_t kept = run();
    if (kept != kN) {
      print_message("  %s seed %llu: removed", name, static_cast<unsigned long long>(seed));
      for (size_t i = 0; i < kN; ++i)
        if (!g_keep[i]) print_message(" z=%.1f", g_z[i]);
      print_message("\n");
    }
    assert_int_equal(kept, kN);
  }
}

void test_cone_trend_kept(void **) { check_trend_kept(Profile::kCone, "cone"); }
void test_quadratic_bottom_kept(void **) {
  check_trend_kept(Profile::kQuadraticBottom, "quadratic bottom");
}
void test_linear_bottom_kept(void **) { check_trend_kept(Profile::kLinearBottom, "linear bottom"); }

void test_paper_mode_misses_spikes_on_trend(void **) {
  // Documents why C6/C7 are on: the paper's literal algorithm (trailing
  // window, no detrend, no noise floor) has MAD ~ 1.5 layer steps on the
  // cone's steep bottom, and a +3 % spike sits inside the threshold.
  fill(Profile::kCone, 2e-4, 1);
  g_s[12] *= 1.03;
  pv::cleanup::Params paper;
  paper.detrend = false;
  paper.centred = false;
  paper.global_noise_floor = false;
  run(paper);
  assert_int_equal(g_keep[12], 1);
  run();
  assert_int_equal(g_keep[12], 0);
}

void test_negative_removed(void **) {
  fill(Profile::kCone, 0.0, 1);
  g_s[5] = -100.0;
  g_s[150] = -1e-9;
  g_s[151] = NAN;
  const size_t kept = run();
  assert_int_equal(g_keep[5], 0);
  assert_int_equal(g_keep[150], 0);
  assert_int_equal(g_keep[151], 0);
  assert_int_equal(kept, kN - 3);
}

void test_constant_keeps_all(void **) {
  fill(Profile::kConstant, 0.0, 1);
  assert_int_equal(run(), kN);
  // Last-bit differences must not be outliers either (the MAD floor, C3).
  for (size_t i = 0; i < kN; i += 7) g_s[i] = std::nextafter(g_s[i], 1e300);
  assert_int_equal(run(), kN);
}

void test_bad_args(void **) {
  fill(Profile::kCone, 0.0, 1);
  assert_int_equal(pv::cleanup::mad_filter(g_z, g_s, kN, pv::cleanup::Params{}, g_keep, g_scratch,
                                           3 * kN - 1),
                   0);
  for (size_t i = 0; i < kN; ++i) assert_int_equal(g_keep[i], 0);
  pv::cleanup::Params p;
  p.window_late = 0;
  assert_int_equal(run(p), 0);
  // Shorter than a window: the whole sequence is the window.
  assert_int_equal(pv::cleanup::mad_filter(g_z, g_s, 4, pv::cleanup::Params{}, g_keep, g_scratch,
                                           12),
                   4);
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_spikes_removed),
      cmocka_unit_test(test_cone_trend_kept),
      cmocka_unit_test(test_quadratic_bottom_kept),
      cmocka_unit_test(test_linear_bottom_kept),
      cmocka_unit_test(test_paper_mode_misses_spikes_on_trend),
      cmocka_unit_test(test_negative_removed),
      cmocka_unit_test(test_constant_keeps_all),
      cmocka_unit_test(test_bad_args),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
