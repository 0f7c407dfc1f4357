// Layer bins: fixed capacity, thinning in place, order independence.
#include <algorithm>
#include <cstring>
#include <vector>

#include "binning/layer_bins.h"
#include "common/point_hash.h"
#include "pv_cmocka.h"

namespace {

std::vector<pv::P3> ring(int n) {
  std::vector<pv::P3> v;
  for (int i = 0; i < n; ++i) v.push_back(pv::P3{float(i) * 0.01f, float(i % 97), 1.0f});
  return v;
}

std::vector<uint64_t> hashes_in(const pv::binning::LayerBins &b, uint32_t j) {
  std::vector<uint64_t> h;
  for (uint32_t i = 0; i < b.count(j); ++i) h.push_back(pv::point_hash(b.points(j)[i]));
  std::sort(h.begin(), h.end());
  return h;
}

void a_full_bin_thins_in_place_and_never_overflows(void **) {
  std::vector<unsigned char> mem(pv::binning::LayerBins::bytes_needed(4, 100));
  pv::binning::LayerBins bins;
  bins.init(mem.data(), 4, 100);
  const auto pts = ring(10000);
  for (const pv::P3 &p : pts) bins.insert(2, p, pv::point_hash(p));
  assert_true(bins.count(2) <= 100);
  assert_true(bins.count(2) >= 25);      // a level halves, so at least a quarter stays
  assert_true(bins.level(2) >= 6);       // 10000 -> <= 100 needs >= 2^6.6
  assert_int_equal(bins.count(1), 0);
  assert_int_equal(bins.stored() + bins.thinned(), 10000);
  // Every survivor passes the bin's level; every passing point survived.
  size_t passing = 0;
  for (const pv::P3 &p : pts) passing += pv::binning::LayerBins::passes(pv::point_hash(p), bins.level(2));
  assert_int_equal(passing, bins.count(2));
}

void kept_points_do_not_depend_on_order(void **) {
  std::vector<unsigned char> m1(pv::binning::LayerBins::bytes_needed(1, 64));
  std::vector<unsigned char> m2(m1.size());
  pv::binning::LayerBins a, b;
  a.init(m1.data(), 1, 64);
  b.init(m2.data(), 1, 64);
  auto pts = ring(3000);
  for (const pv::P3 &p : pts) a.insert(0, p, pv::point_hash(p));
  std::reverse(pts.begin(), pts.end());
  std::rotate(pts.begin(), pts.begin() + 1234, pts.end());
  for (const pv::P3 &p : pts) b.insert(0, p, pv::point_hash(p));
  assert_int_equal(a.level(0), b.level(0));
  assert_true(hashes_in(a, 0) == hashes_in(b, 0));
}

// Ranks (one byte a slot) only spare the hashing: the same points in the
// same order, in every bin, as bins that hash again.
void ranks_keep_the_same_points_in_the_same_order(void **) {
  std::vector<unsigned char> m1(pv::binning::LayerBins::bytes_needed(3, 64));
  std::vector<unsigned char> m2(pv::binning::LayerBins::bytes_needed(3, 64, true));
  assert_int_equal(m2.size() - m1.size(), 3 * 64);
  pv::binning::LayerBins a, b;
  a.init(m1.data(), 3, 64);
  b.init(m2.data(), 3, 64, true);
  assert_false(a.has_ranks());
  assert_true(b.has_ranks());
  const auto pts = ring(20000);
  for (size_t i = 0; i < pts.size(); ++i) {
    const uint32_t j = uint32_t(i * 7 % 3);
    a.insert(j, pts[i], pv::point_hash(pts[i]));
    b.insert(j, pts[i], pv::point_hash(pts[i]));
  }
  for (uint32_t j = 0; j < 3; ++j) {
    assert_true(a.level(j) >= 5);  // 6,667 points each into 64 slots
    assert_int_equal(a.level(j), b.level(j));
    assert_int_equal(a.count(j), b.count(j));
    assert_memory_equal(a.points(j), b.points(j), a.count(j) * sizeof(pv::P3));
  }
  assert_int_equal(a.stored(), b.stored());
  assert_int_equal(a.thinned(), b.thinned());
  // The rank is the level test: rank(h) >= L exactly when h passes level L.
  for (const pv::P3 &p : ring(300)) {
    const uint64_t h = pv::point_hash(p);
    for (uint8_t l = 0; l < 64; ++l) {
      assert_int_equal(pv::binning::LayerBins::rank(h) >= l, pv::binning::LayerBins::passes(h, l));
    }
  }
  assert_int_equal(pv::binning::LayerBins::rank(0), 64);
  assert_int_equal(pv::binning::LayerBins::rank(1), 63);
  assert_int_equal(pv::binning::LayerBins::rank(~uint64_t(0)), 0);
}

// The floor: 8 dense bins (wall layers) at 2,000 points each against 64
// slots, one sparse bin (a stray's layer) at 40. Without a floor the sparse
// bin keeps all 40 while the dense ones keep one point in 32 or fewer; with a
// floor of 4 bins it thins at the dense bins' rate, and what survives still
// does not depend on the order the points came in.
struct Stream {
  uint32_t bin;
  pv::P3 p;
};
std::vector<Stream> dense_and_sparse() {
  std::vector<Stream> s;
  for (uint32_t j = 0; j < 8; ++j) {
    for (int i = 0; i < 2000; ++i) s.push_back({j, pv::P3{float(i) * 0.01f, float(j), 2.0f}});
  }
  for (int i = 0; i < 40; ++i) s.push_back({8, pv::P3{float(i) * 0.37f, 8.0f, 5.0f}});
  return s;
}
void fill(pv::binning::LayerBins &b, const std::vector<Stream> &s) {
  for (const Stream &x : s) b.insert(x.bin, x.p, pv::point_hash(x.p));
}

void a_sparse_bin_thins_at_the_dense_bins_rate(void **) {
  const size_t bytes = pv::binning::LayerBins::bytes_needed(9, 64);
  std::vector<unsigned char> m0(bytes), m1(bytes), m2(bytes);
  pv::binning::LayerBins none, a, b;
  none.init(m0.data(), 9, 64);
  a.init(m1.data(), 9, 64, false, 4);
  b.init(m2.data(), 9, 64, false, 4);
  auto s = dense_and_sparse();
  fill(none, s);
  assert_int_equal(none.count(8), 40);
  assert_int_equal(none.level(8), 0);
  fill(a, s);
  // 2,000 -> <= 64 slots needs level >= 5 in every dense bin.
  assert_true(a.floor_level() >= 5);
  for (uint32_t j = 0; j < 8; ++j) assert_true(a.level(j) >= a.floor_level());
  assert_int_equal(a.level(8), a.floor_level());
  assert_true(a.count(8) < 40 / 8);  // 40 points at 1 in 32: a few at most
  size_t passing = 0;
  for (int i = 0; i < 40; ++i) {
    passing += pv::binning::LayerBins::passes(pv::point_hash(s[s.size() - 40 + size_t(i)].p), a.level(8));
  }
  assert_int_equal(passing, a.count(8));
  assert_int_equal(a.stored() + a.thinned(), s.size());
  // The sparse bin first, the dense bins interleaved: the same survivors.
  std::rotate(s.begin(), s.end() - 40, s.end());
  for (size_t i = 40; i + 7 < s.size(); i += 7) std::swap(s[i], s[s.size() - 1 - (i - 40)]);
  fill(b, s);
  assert_int_equal(a.floor_level(), b.floor_level());
  for (uint32_t j = 0; j < 9; ++j) {
    assert_int_equal(a.level(j), b.level(j));
    assert_true(hashes_in(a, j) == hashes_in(b, j));
  }
}

void clear_forgets_everything(void **) {
  std::vector<unsigned char> mem(pv::binning::LayerBins::bytes_needed(2, 64));
  pv::binning::LayerBins bins;
  bins.init(mem.data(), 2, 64);
  for (const pv::P3 &p : ring(500)) bins.insert(1, p, pv::point_hash(p));
  bins.clear();
  assert_int_equal(bins.count(1), 0);
  assert_int_equal(bins.level(1), 0);
  assert_int_equal(bins.stored(), 0);
}

// The index (a scan sent again, session repeat mode): turned on part way,
// the bins keep the same points as bins without it, holds() finds every
// point a bin holds and none it does not, through tails merged into the
// sorted prefix and through thinning (a floor of 2 bins, so thinning one
// bin thins the others); ranks stay each point's rank.
void the_index_finds_what_a_bin_holds(void **) {
  constexpr uint32_t kLayers = 3, kCap = 256;
  std::vector<unsigned char> m1(pv::binning::LayerBins::bytes_needed(kLayers, kCap, true));
  std::vector<unsigned char> m2(pv::binning::LayerBins::bytes_needed(kLayers, kCap, true, true));
  assert_int_equal(m2.size() - m1.size(), kLayers * sizeof(uint32_t));
  pv::binning::LayerBins plain, indexed;
  plain.init(m1.data(), kLayers, kCap, true, 2);
  indexed.init(m2.data(), kLayers, kCap, true, 2, true);
  const auto pts = ring(9000);
  for (size_t i = 0; i < pts.size(); ++i) {
    if (i == 300) {
      assert_false(plain.start_index());  // no room for it
      assert_true(indexed.start_index());
      assert_int_equal(indexed.tail_max(), 32);
    }
    const uint32_t j = uint32_t(i % kLayers);
    const uint64_t h = pv::point_hash(pts[i]);
    assert_int_equal(plain.insert(j, pts[i], h), indexed.insert(j, pts[i], h));
  }
  assert_true(indexed.indexed());
  for (uint32_t j = 0; j < kLayers; ++j) {
    assert_true(indexed.level(j) >= 3);  // 3,000 points into 256 slots
    assert_int_equal(plain.level(j), indexed.level(j));
    assert_true(hashes_in(plain, j) == hashes_in(indexed, j));
  }
  for (size_t i = 0; i < pts.size(); ++i) {
    const uint32_t j = uint32_t(i % kLayers);
    const pv::P3 *b = plain.points(j);
    const bool held = std::any_of(b, b + plain.count(j), [&](const pv::P3 &q) {
      return std::memcmp(&q, &pts[i], sizeof q) == 0;
    });
    assert_int_equal(indexed.holds(j, pts[i]), held);
    assert_false(indexed.holds((j + 1) % kLayers, pts[i]));
  }
}

// Copies stored before the index starts (a scan sent again, before the
// repeat is seen) are dropped when it sorts the bins: one of each stays.
void the_index_keeps_one_of_each_copy(void **) {
  std::vector<unsigned char> mem(pv::binning::LayerBins::bytes_needed(2, 512, true, true));
  pv::binning::LayerBins b;
  b.init(mem.data(), 2, 512, true, 0, true);
  const auto pts = ring(100);
  for (int copy = 0; copy < 3; ++copy) {
    for (const pv::P3 &p : pts) assert_true(b.insert(0, p, pv::point_hash(p)));
  }
  assert_int_equal(b.count(0), 300);
  assert_true(b.start_index());
  assert_int_equal(b.count(0), 100);
  assert_int_equal(b.stored(), 100);
  for (const pv::P3 &p : pts) assert_true(b.holds(0, p));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(a_full_bin_thins_in_place_and_never_overflows),
      cmocka_unit_test(kept_points_do_not_depend_on_order),
      cmocka_unit_test(ranks_keep_the_same_points_in_the_same_order),
      cmocka_unit_test(a_sparse_bin_thins_at_the_dense_bins_rate),
      cmocka_unit_test(clear_forgets_everything),
      cmocka_unit_test(the_index_finds_what_a_bin_holds),
      cmocka_unit_test(the_index_keeps_one_of_each_copy),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
