// Unit tests of pv::thinning (adaptive thinning, paper 3.5).
// Area is measured here independently of core/area: the exact area of the
// polygon through the points sorted by polar angle about the origin
// (shoelace), compared between the kept points and all the points.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "thinning/adaptive_thinning.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

using pv::XY;
namespace th = pv::thinning;

namespace {

using pv::test::kPi;
using pv::test::Rng;


// Ring of radius r with radial noise; angle drawn with density
// proportional to 1 + a cos(theta) (rejection sampling).
std::vector<XY> noisy_ring(size_t n, double r_mm, double noise_mm, double a, uint64_t seed) {
  Rng rng{seed};
  std::vector<XY> v;
  v.reserve(n);
  while (v.size() < n) {
    const double t = 2.0 * kPi * rng.uniform();
    if (rng.uniform() * (1.0 + a) > 1.0 + a * std::cos(t)) continue;
    const double rr = r_mm + noise_mm * rng.gauss();
    v.push_back(XY{rr * std::cos(t), rr * std::sin(t)});
  }
  return v;
}

// Exact area of the polygon through the points in polar-angle order.
double polygon_area_mm2(std::vector<XY> v) {
  std::sort(v.begin(), v.end(), [](const XY &a, const XY &b) {
    return std::atan2(a.y_mm, a.x_mm) < std::atan2(b.y_mm, b.x_mm);
  });
  double s = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    const XY &a = v[i];
    const XY &b = v[(i + 1) % v.size()];
    s += a.x_mm * b.y_mm - b.x_mm * a.y_mm;
  }
  return 0.5 * std::fabs(s);
}

struct Ws {
  std::vector<unsigned char> block;
  th::Workspace ws;
  explicit Ws(size_t n) : block(th::workspace_bytes(n)) {
    assert_true(th::make_workspace(block.data(), block.size(), n, &ws));
  }
};

size_t thin(std::vector<XY> &v, const th::Params &p = th::Params()) {
  Ws w(v.size());
  const size_t k = th::thin_layer(v.data(), v.size(), p, w.ws);
  v.resize(k);
  return k;
}

bool is_canonical(const std::vector<XY> &v) {
  for (size_t i = 1; i < v.size(); ++i) {
    const XY &a = v[i - 1], &b = v[i];
    if (a.x_mm > b.x_mm || (a.x_mm == b.x_mm && a.y_mm > b.y_mm)) return false;
  }
  return true;
}

void test_dense_noisy_ring_keeps_area(void **) {
  const double r = 110.0;
  std::vector<XY> all = noisy_ring(20000, r, 0.1, 0.9, 1);
  std::vector<XY> kept = all;
  const size_t k = thin(kept);
  const double a_all = polygon_area_mm2(all);
  const double a_kept = polygon_area_mm2(kept);
  const double rel = (a_kept - a_all) / a_all;
  const double a_true = kPi * r * r;
  print_message("dense ring: kept %zu of %zu (%.2f %%); area kept vs all %+.5f %%; "
                "all vs pi r^2 %+.5f %%; kept vs pi r^2 %+.5f %%\n",
                k, all.size(), 100.0 * static_cast<double>(k) / 20000.0, 100.0 * rel,
                100.0 * (a_all - a_true) / a_true, 100.0 * (a_kept - a_true) / a_true);
  assert_true(k < all.size() / 2);
  assert_true(k > 200);  // still a contour, not a handful of points
  assert_true(std::fabs(rel) < 5e-4);
  assert_true(is_canonical(kept));
}

void test_sparse_half_kept_dense_half_thinned(void **) {
  // Upper half (y > 0): 0.1 mm pitch; lower half: 1.0 mm pitch (10x sparser).
  const double r = 110.0;
  Rng rng{7};
  std::vector<XY> v;
  const size_t n_dense = static_cast<size_t>(kPi * r / 0.1);
  const size_t n_sparse = static_cast<size_t>(kPi * r / 1.0);
  for (size_t i = 0; i < n_dense; ++i) {
    const double t = kPi * (static_cast<double>(i) + 0.5) / static_cast<double>(n_dense);
    const double rr = r + 0.05 * rng.gauss();
    v.push_back(XY{rr * std::cos(t), rr * std::sin(t)});
  }
  for (size_t i = 0; i < n_sparse; ++i) {
    const double t = -kPi * (static_cast<double>(i) + 0.5) / static_cast<double>(n_sparse);
    const double rr = r + 0.05 * rng.gauss();
    v.push_back(XY{rr * std::cos(t), rr * std::sin(t)});
  }
  thin(v);
  size_t up = 0, down = 0;
  for (const XY &q : v) (q.y_mm > 0 ? up : down) += 1;
  print_message("half-dense ring: dense half kept %zu of %zu (%.1f %%), sparse half kept "
                "%zu of %zu (%.1f %%)\n",
                up, n_dense, 100.0 * static_cast<double>(up) / static_cast<double>(n_dense),
                down, n_sparse, 100.0 * static_cast<double>(down) / static_cast<double>(n_sparse));
  assert_true(static_cast<double>(down) >= 0.95 * static_cast<double>(n_sparse));
  assert_true(static_cast<double>(up) <= 0.30 * static_cast<double>(n_dense));
}

void test_shuffled_input_same_bits(void **) {
  std::vector<XY> a = noisy_ring(6000, 110.0, 0.1, 0.9, 3);
  std::vector<XY> b = a;
  Rng rng{11};
  for (size_t i = b.size() - 1; i > 0; --i) std::swap(b[i], b[rng.next() % (i + 1)]);
  std::reverse(a.begin(), a.end());
  const size_t ka = thin(a), kb = thin(b);
  assert_int_equal(ka, kb);
  assert_memory_equal(a.data(), b.data(), ka * sizeof(XY));
}

void test_too_few_points_kept(void **) {
  std::vector<XY> v = {{3, 1}, {1, 2}, {2, 2}, {1, 1}, {0, 5}};
  assert_int_equal(thin(v), 5);  // n < k + 1 with k = 8
  assert_true(is_canonical(v));
  std::vector<XY> one = {{1, 1}};
  assert_int_equal(thin(one), 1);
  Ws w(1);
  assert_int_equal(th::thin_layer(nullptr, 0, th::Params(), w.ws), 0);
  // k above the fixed kNN array is clamped, not overrun.
  std::vector<XY> ring = noisy_ring(500, 110.0, 0.1, 0.0, 5);
  th::Params big;
  big.knn_k = 1000;
  assert_true(thin(ring, big) > 0);
}

void test_duplicates(void **) {
  std::vector<XY> base = noisy_ring(2000, 110.0, 0.1, 0.5, 9);
  std::vector<XY> v;
  for (int rep = 0; rep < 3; ++rep) v.insert(v.end(), base.begin(), base.end());
  const size_t k = thin(v);
  assert_true(k > 0 && k <= base.size());
  for (size_t i = 1; i < k; ++i)  // a square always holds all copies: one survives
    assert_false(v[i].x_mm == v[i - 1].x_mm && v[i].y_mm == v[i - 1].y_mm);
  std::vector<XY> same(100, XY{5.0, -2.0});  // rho_max == rho_min, d_i = 0
  assert_int_equal(thin(same), 1);
  assert_true(same[0].x_mm == 5.0 && same[0].y_mm == -2.0);
}

void test_non_finite_dropped_and_small_workspace(void **) {
  std::vector<XY> v = noisy_ring(300, 110.0, 0.1, 0.0, 13);
  v[10].x_mm = NAN;
  v[20].y_mm = INFINITY;
  const size_t k = thin(v);
  for (size_t i = 0; i < k; ++i) assert_true(std::isfinite(v[i].x_mm) && std::isfinite(v[i].y_mm));
  // Workspace smaller than the layer: nothing done, nothing lost.
  std::vector<XY> w = noisy_ring(300, 110.0, 0.1, 0.0, 13);
  std::vector<XY> copy = w;
  Ws small(100);
  assert_int_equal(th::thin_layer(w.data(), w.size(), th::Params(), small.ws), w.size());
  assert_memory_equal(w.data(), copy.data(), w.size() * sizeof(XY));
  unsigned char tiny[8];
  th::Workspace ws;
  assert_false(th::make_workspace(tiny, sizeof tiny, 100, &ws));
  assert_int_equal(th::workspace_bytes_per_point(), 21);
}

// Independent truth for the neighbour grid: brute force over all pairs, the
// k + 1 smallest squared distances summed as square roots in ascending
// order, divided by k. Must agree to the bit, on rings, on a lattice (many
// exactly equal distances), with duplicates and with a lone far point.
std::vector<double> brute_force_knn_mean(const std::vector<XY> &v, uint32_t k) {
  std::vector<double> out(v.size()), d2(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    for (size_t j = 0; j < v.size(); ++j) {
      const double dx = v[i].x_mm - v[j].x_mm, dy = v[i].y_mm - v[j].y_mm;
      d2[j] = dx * dx + dy * dy;
    }
    std::partial_sort(d2.begin(), d2.begin() + k + 1, d2.end());
    double sum = 0.0;
    for (uint32_t j = 0; j <= k; ++j) sum += std::sqrt(d2[j]);
    out[i] = std::max(sum / static_cast<double>(k), th::kMinMeanDistMm);
  }
  return out;
}

void check_knn_against_brute_force(std::vector<XY> v, uint32_t k) {
  v.resize(th::canonicalize(v.data(), v.size()));
  Ws w(v.size());
  std::vector<double> got(v.size());
  assert_true(th::mean_knn_distances(v.data(), v.size(), k, w.ws, got.data()));
  const std::vector<double> want = brute_force_knn_mean(v, k);
  assert_memory_equal(got.data(), want.data(), v.size() * sizeof(double));
}

void test_knn_grid_is_exact(void **) {
  check_knn_against_brute_force(noisy_ring(1500, 110.0, 0.1, 0.9, 21), 8);
  check_knn_against_brute_force(noisy_ring(700, 50.0, 2.0, 0.0, 22), 3);
  std::vector<XY> lattice;  // 0.5 mm lattice: ties at every distance
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 20; ++j) lattice.push_back(XY{0.5 * i, 0.5 * j});
  check_knn_against_brute_force(lattice, 8);
  check_knn_against_brute_force(lattice, 32);
  std::vector<XY> dup = noisy_ring(300, 110.0, 0.1, 0.0, 23);
  dup.insert(dup.end(), dup.begin(), dup.begin() + 100);
  dup.push_back(XY{1000.0, -1000.0});  // far outlier: a search across the grid
  check_knn_against_brute_force(dup, 8);
  std::vector<XY> line;  // degenerate extent in y
  for (int i = 0; i < 200; ++i) line.push_back(XY{0.37 * i, 2.0});
  check_knn_against_brute_force(line, 8);
}

void test_spacing_mapping(void **) {
  assert_true(th::spacing_from_density(1.0, 1.0, 3.0, 1.0) == 0.5);
  assert_true(th::spacing_from_density(3.0, 1.0, 3.0, 1.0) == 2.0);
  assert_true(th::spacing_from_density(2.0, 1.0, 3.0, 1.0) == 1.25);
  assert_true(th::spacing_from_density(9.0, 1.0, 3.0, 1.0) == 2.0);  // clamped
  assert_true(th::spacing_from_density(2.0, 2.0, 2.0, 1.0) == 0.5);  // uniform layer
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_dense_noisy_ring_keeps_area),
      cmocka_unit_test(test_sparse_half_kept_dense_half_thinned),
      cmocka_unit_test(test_shuffled_input_same_bits),
      cmocka_unit_test(test_too_few_points_kept),
      cmocka_unit_test(test_duplicates),
      cmocka_unit_test(test_non_finite_dropped_and_small_workspace),
      cmocka_unit_test(test_spacing_mapping),
      cmocka_unit_test(test_knn_grid_is_exact),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
