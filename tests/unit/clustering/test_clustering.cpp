// Unit tests of pv::clustering (per-layer clustering, paper 3.6).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "clustering/clustering.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

using pv::XY;
namespace cl = pv::clustering;

namespace {

using pv::test::kPi;
using pv::test::Rng;


// n points on the arc [t0, t1] (radians) of an ellipse with semi-axes a, b,
// radial noise noise_mm.
std::vector<XY> arc(size_t n, double a_mm, double b_mm, double t0, double t1,
                    double noise_mm, uint64_t seed) {
  Rng rng{seed};
  std::vector<XY> v;
  for (size_t i = 0; i < n; ++i) {
    const double t = t0 + (t1 - t0) * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double k = 1.0 + noise_mm * rng.gauss() / a_mm;
    v.push_back(XY{k * a_mm * std::cos(t), k * b_mm * std::sin(t)});
  }
  return v;
}

std::vector<XY> circle(size_t n, double r_mm, double noise_mm, uint64_t seed) {
  return arc(n, r_mm, r_mm, 0.0, 2.0 * kPi, noise_mm, seed);
}

size_t run(std::vector<XY> &v, const cl::Params &p, cl::Info *info) {
  std::vector<double> scratch(v.size());
  const size_t k = cl::cluster_layer(v.data(), v.size(), p, scratch.data(), scratch.size(), info);
  v.resize(k);
  return k;
}

size_t count_radius_between(const std::vector<XY> &v, double lo, double hi) {
  size_t c = 0;
  for (const XY &q : v) {
    const double r = std::hypot(q.x_mm, q.y_mm);
    c += (r >= lo && r <= hi) ? 1u : 0u;
  }
  return c;
}

cl::Shape shape_of(const std::vector<XY> &v) {
  return cl::classify(cl::measure_morphology(v.data(), v.size(), cl::Params()), cl::Params());
}

void test_interior_noise_removed_ring_kept(void **) {
  const double r = 110.0;
  std::vector<XY> v = circle(2000, r, 0.1, 1);
  Rng rng{2};
  for (int i = 0; i < 100; ++i) {  // 5 %: uniform in the disc of radius r - 30
    const double rr = (r - 30.0) * std::sqrt(rng.uniform());
    const double t = 2.0 * kPi * rng.uniform();
    v.push_back(XY{rr * std::cos(t), rr * std::sin(t)});
  }
  cl::Info info;
  const size_t k = run(v, cl::Params(), &info);
  print_message("ring + 5 %% interior noise: kept %zu of 2100, r_base %.3f mm, band [%.3f, %.3f]\n",
                k, info.r_base_mm, info.r_low_mm, info.r_high_mm);
  assert_int_equal(static_cast<int>(info.shape), static_cast<int>(cl::Shape::NearCircular));
  assert_int_equal(k, 2000);
  assert_int_equal(count_radius_between(v, r - 1.0, r + 1.0), 2000);
  for (size_t i = 1; i < k; ++i)  // compacted in canonical order
    assert_true(v[i - 1].x_mm < v[i].x_mm ||
                (v[i - 1].x_mm == v[i].x_mm && v[i - 1].y_mm <= v[i].y_mm));
}

void test_classification(void **) {
  assert_int_equal(static_cast<int>(shape_of(circle(2000, 110.0, 0.1, 3))),
                   static_cast<int>(cl::Shape::NearCircular));
  // Mildly elliptic pit 220 x 190: elongation 30 mm < 50 -> still circular.
  assert_int_equal(static_cast<int>(shape_of(arc(2000, 110.0, 95.0, 0.0, 2 * kPi, 0.1, 4))),
                   static_cast<int>(cl::Shape::NearCircular));
  const std::vector<XY> ellipse = arc(2000, 100.0, 50.0, 0.0, 2 * kPi, 0.1, 5);  // 200 x 100
  const cl::Morphology me = cl::measure_morphology(ellipse.data(), ellipse.size(), cl::Params());
  print_message("ellipse 200x100: elongation %.1f dy_x %.1f dx_y %.1f\n", me.elongation_mm,
                me.dy_x_mm, me.dx_y_mm);
  assert_int_equal(static_cast<int>(shape_of(ellipse)), static_cast<int>(cl::Shape::Crescent));
  assert_int_equal(static_cast<int>(shape_of(arc(700, 110.0, 110.0, -kPi / 3, kPi / 3, 0.1, 6))),
                   static_cast<int>(cl::Shape::Crescent));  // 120 degree arc
  // C open towards +X: elongation only 32 mm, but both horns sit at max X.
  const std::vector<XY> c_open = arc(1600, 110.0, 110.0, kPi / 4, 7 * kPi / 4, 0.1, 7);
  const cl::Morphology mc = cl::measure_morphology(c_open.data(), c_open.size(), cl::Params());
  print_message("C open to +X: elongation %.1f dy_x %.1f dx_y %.1f\n", mc.elongation_mm,
                mc.dy_x_mm, mc.dx_y_mm);
  assert_true(mc.elongation_mm < 50.0 && mc.dy_x_mm > 80.0);
  assert_int_equal(static_cast<int>(shape_of(c_open)), static_cast<int>(cl::Shape::Crescent));
  // C open towards +Y: dx_y.
  const std::vector<XY> c_up = arc(1600, 110.0, 110.0, 3 * kPi / 4, 9 * kPi / 4, 0.1, 8);
  const cl::Morphology mu = cl::measure_morphology(c_up.data(), c_up.size(), cl::Params());
  assert_true(mu.dx_y_mm > 80.0);
}

void test_crescent_keeps_arc_drops_far_points(void **) {
  std::vector<XY> v = arc(700, 110.0, 110.0, -kPi / 3, kPi / 3, 0.1, 9);
  Rng rng{10};
  for (int i = 0; i < 14; ++i) {  // 2 % far outside the arc, r = 200 mm
    const double t = (rng.uniform() - 0.5) * 2.0 * kPi / 3.0;
    v.push_back(XY{200.0 * std::cos(t), 200.0 * std::sin(t)});
  }
  // Points near the arc's centre of curvature would NOT be removed: relative
  // to the centroid (~(90, 0)) they sit at ~90 mm, inside the band [~13,
  // ~104] that a 120-degree arc needs (a limitation of the paper's rule).
  cl::Info info;
  const size_t k = run(v, cl::Params(), &info);
  print_message("120-degree arc + 2 %% far strays: kept %zu of 714, centre (%.2f, %.2f), "
                "band [%.2f, %.2f]\n",
                k, info.center_x_mm, info.center_y_mm, info.r_low_mm, info.r_high_mm);
  assert_int_equal(static_cast<int>(info.shape), static_cast<int>(cl::Shape::Crescent));
  assert_int_equal(k, 700);
  assert_int_equal(count_radius_between(v, 109.0, 111.0), 700);
}

void test_circle_far_outliers(void **) {
  // Four stray points at r = 140 (one at max X: the layer stays near-circular).
  std::vector<XY> base = circle(2000, 110.0, 0.1, 11);
  for (int i = 0; i < 4; ++i)
    base.push_back(XY{140.0 * std::cos(i * kPi / 2), 140.0 * std::sin(i * kPi / 2)});
  // Paper's literal r_base = max: the strays define r_base and the band
  // [120, 160] loses the whole wall. Pinned here as the documented weakness.
  std::vector<XY> literal = base;
  cl::Info info;
  const size_t k_lit = run(literal, cl::Params(), &info);
  print_message("circle + 4 strays at r=140, paper r_base=max: r_base %.2f, kept %zu of 2004\n",
                info.r_base_mm, k_lit);
  assert_int_equal(static_cast<int>(info.shape), static_cast<int>(cl::Shape::NearCircular));
  assert_int_equal(k_lit, 4);
  // Robust r_base (median distance): strays beyond the band removed, wall kept.
  cl::Params robust;
  robust.circle_rbase_quantile = 0.5;
  std::vector<XY> v = base;
  const size_t k = run(v, robust, &info);
  print_message("same, r_base = median: r_base %.2f, kept %zu of 2004\n", info.r_base_mm, k);
  assert_int_equal(k, 2000);
  assert_int_equal(count_radius_between(v, 109.0, 111.0), 2000);
}

void test_order_independent(void **) {
  for (int which = 0; which < 2; ++which) {
    std::vector<XY> a = which == 0 ? circle(1500, 110.0, 0.2, 12)
                                   : arc(900, 110.0, 110.0, 0.3, 2.6, 0.2, 13);
    Rng rng{14};
    // Strays: over the circle's inside, or near the arc's chord (keeps it a crescent).
    const double box = which == 0 ? 150.0 : 40.0, y0 = which == 0 ? 0.0 : 50.0;
    for (int i = 0; i < 60; ++i)
      a.push_back(XY{box * (rng.uniform() - 0.5), y0 + box * (rng.uniform() - 0.5)});
    const size_t n = a.size();
    std::vector<XY> b = a;
    for (size_t i = b.size() - 1; i > 0; --i) std::swap(b[i], b[rng.next() % (i + 1)]);
    std::reverse(a.begin(), a.end());
    cl::Info ia, ib;
    const size_t ka = run(a, cl::Params(), &ia);
    const size_t kb = run(b, cl::Params(), &ib);
    assert_int_equal(ka, kb);
    assert_memory_equal(a.data(), b.data(), ka * sizeof(XY));
    assert_true(ia.shape == ib.shape);
    assert_memory_equal(&ia.center_x_mm, &ib.center_x_mm, sizeof(double));
    assert_memory_equal(&ia.center_y_mm, &ib.center_y_mm, sizeof(double));
    assert_memory_equal(&ia.r_base_mm, &ib.r_base_mm, sizeof(double));
    assert_memory_equal(&ia.r_low_mm, &ib.r_low_mm, sizeof(double));
    assert_memory_equal(&ia.r_high_mm, &ib.r_high_mm, sizeof(double));
    print_message("order test %d: shape %d kept %zu of %zu\n", which, static_cast<int>(ia.shape),
                  ka, n);
    assert_int_equal(static_cast<int>(ia.shape), which);
  }
}

void test_edge_cases(void **) {
  cl::Info info;
  assert_int_equal(cl::cluster_layer(nullptr, 0, cl::Params(), nullptr, 0, &info), 0);
  std::vector<XY> one = {{1.0, 2.0}};
  assert_int_equal(run(one, cl::Params(), nullptr), 1);
  // Crescent without enough scratch: nothing removed.
  std::vector<XY> v = arc(300, 110.0, 110.0, -kPi / 3, kPi / 3, 0.1, 15);
  v.push_back(XY{0.0, 0.0});
  double scratch[4];
  assert_int_equal(cl::cluster_layer(v.data(), v.size(), cl::Params(), scratch, 4, &info), 301);
  // Non-finite points dropped.
  std::vector<XY> w = circle(200, 110.0, 0.1, 16);
  w[3].x_mm = NAN;
  assert_int_equal(run(w, cl::Params(), &info), 199);
  // Paper's literal angle window [pi/2, pi] keeps only that quadrant.
  std::vector<XY> c = arc(900, 110.0, 110.0, 0.0, kPi, 0.1, 17);
  cl::Params lit;
  lit.crescent_angle_min_rad = kPi / 2;
  lit.crescent_angle_max_rad = kPi;
  const size_t kc = run(c, lit, &info);
  assert_int_equal(static_cast<int>(info.shape), static_cast<int>(cl::Shape::Crescent));
  print_message("half circle, paper window [pi/2, pi]: kept %zu of 900\n", kc);
  for (const XY &q : c) assert_true(q.x_mm <= info.center_x_mm);
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_interior_noise_removed_ring_kept),
      cmocka_unit_test(test_classification),
      cmocka_unit_test(test_crescent_keeps_arc_drops_far_points),
      cmocka_unit_test(test_circle_far_outliers),
      cmocka_unit_test(test_order_independent),
      cmocka_unit_test(test_edge_cases),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
