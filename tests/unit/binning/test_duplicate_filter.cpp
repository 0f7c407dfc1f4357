// Duplicate filter: exact and near-exact repeats within the window are
// dropped, distinct points are kept, the window forgets old points.
#include <cmath>
#include <vector>

#include "binning/duplicate_filter.h"
#include "test_rng.h"
#include "pv_cmocka.h"

namespace {

using pv::P3;
using pv::binning::DuplicateFilter;

struct Filter {
  std::vector<uint64_t> mem = std::vector<uint64_t>(DuplicateFilter::bytes_needed() / 8);
  DuplicateFilter f;
  Filter() { f.init(mem.data()); }
};

P3 random_point(pv::test::Rng *rng) {
  return P3{float(800 * rng->uniform() - 400), float(800 * rng->uniform() - 400),
            float(500 + 1000 * rng->uniform())};
}

void exact_repeats_are_dropped(void **) {
  Filter f;
  pv::test::Rng rng{1};
  std::vector<P3> pts;
  for (int i = 0; i < 10000; ++i) pts.push_back(random_point(&rng));
  for (const P3 &p : pts) assert_false(f.f.seen_before(p));
  for (const P3 &p : pts) assert_true(f.f.seen_before(p));
}

void minus_zero_is_zero(void **) {
  Filter f;
  assert_false(f.f.seen_before(P3{0.0f, 1.0f, 2.0f}));
  assert_true(f.f.seen_before(P3{-0.0f, 1.0f, 2.0f}));
}

// One ulp (up to 2 m) or two (up to 1 m) away on every axis, in both
// directions: the same point.
void near_exact_repeats_are_dropped(void **) {
  Filter f;
  pv::test::Rng rng{2};
  std::vector<P3> pts;
  for (int i = 0; i < 20000; ++i) pts.push_back(random_point(&rng));
  for (const P3 &p : pts) assert_false(f.f.seen_before(p));
  for (size_t i = 0; i < pts.size(); ++i) {
    const float dir = (i % 2) ? INFINITY : -INFINITY;
    P3 q = pts[i];
    const int ulps = std::fabs(q.z_mm) < 1000.0f ? 2 : 1;
    for (int k = 0; k < ulps; ++k) {
      q.x_mm = std::nextafter(q.x_mm, dir);
      q.y_mm = std::nextafter(q.y_mm, -dir);
      q.z_mm = std::nextafter(q.z_mm, dir);
    }
    assert_true(f.f.seen_before(q));
  }
}

// Straddling a cell boundary (cells are 2^-7 mm): 0.05 um apart, in
// different cells, still one point.
void near_exact_across_a_cell_boundary(void **) {
  Filter f;
  const float edge = 100.0f + 3.0f / 128.0f;  // exactly on a boundary
  assert_false(f.f.seen_before(P3{edge - 0.00003f, 5.0f, 7.0f}));
  assert_true(f.f.seen_before(P3{edge + 0.00002f, 5.0f, 7.0f}));
}

// The same on each axis, from either side, at a boundary inside a block of
// 16 cells (the neighbour shares the bucket) and at a block's boundary (it
// does not), the other axes far from any boundary; a point in the cell
// after next is another point.
void near_exact_across_a_boundary_on_each_axis(void **) {
  const float edges[2] = {100.0f + 3.0f / 128.0f, 100.0f + 16.0f / 128.0f};  // cell 12803, 12816
  for (int axis = 0; axis < 3; ++axis) {
    for (const float edge : edges) {
      for (int below_first = 0; below_first < 2; ++below_first) {
        Filter f;
        P3 below{5.3f, -7.3f, 11.3f}, above = below, far = below;  // 0.4 of a cell from edges
        float *b = &below.x_mm + axis, *a = &above.x_mm + axis, *o = &far.x_mm + axis;
        *b = edge - 0.00003f;
        *a = edge + 0.00002f;
        *o = edge + 1.3f / 128.0f;  // the next cell but one, far from its boundaries
        assert_false(f.f.seen_before(below_first ? below : above));
        assert_true(f.f.seen_before(below_first ? above : below));
        assert_false(f.f.seen_before(far));
      }
    }
  }
}

// Points 20 um apart on one axis are distinct (above the cell and the
// tolerance): none is dropped.
void close_but_distinct_points_are_kept(void **) {
  Filter f;
  for (int i = 0; i < 1000; ++i) {
    assert_false(f.f.seen_before(P3{10.0f + 0.02f * float(i), -20.0f, 600.0f}));
  }
}

// A point is still known after 8 frames of new points (4 frames is the
// designed window; 8 fail with probability 4e-9), and forgotten after a
// million (its bucket has seen far more than 15 newer points).
void the_window_remembers_recent_and_forgets_old_points(void **) {
  Filter f;
  pv::test::Rng rng{3};
  const P3 first{1.5f, 2.5f, 3.5f};
  assert_false(f.f.seen_before(first));
  for (uint32_t i = 0; i < 8 * 4096; ++i) f.f.seen_before(random_point(&rng));
  assert_true(f.f.seen_before(first));
  for (uint32_t i = 0; i < 1000000; ++i) f.f.seen_before(random_point(&rng));
  assert_false(f.f.seen_before(first));
}

void clear_forgets_everything(void **) {
  Filter f;
  const P3 p{1.0f, 2.0f, 3.0f};
  assert_false(f.f.seen_before(p));
  f.f.clear();
  assert_false(f.f.seen_before(p));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(exact_repeats_are_dropped),
      cmocka_unit_test(minus_zero_is_zero),
      cmocka_unit_test(near_exact_repeats_are_dropped),
      cmocka_unit_test(near_exact_across_a_cell_boundary),
      cmocka_unit_test(near_exact_across_a_boundary_on_each_axis),
      cmocka_unit_test(close_but_distinct_points_are_kept),
      cmocka_unit_test(the_window_remembers_recent_and_forgets_old_points),
      cmocka_unit_test(clear_forgets_everything),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
