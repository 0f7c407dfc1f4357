// The rim's height from the points about the rim plane: a wall's top edge
// and a container's lip at known heights, however many points were stored
// and whatever each stands for.
#include <cmath>

#include "rim/rim_profile.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::Rng;

// A wall ending at edge_mm (about the plane at 0) seen n times per mm of
// height down to 6 mm under the plane, its density rising by `rise` over
// its last 2 mm (the scanner sees the top from more directions), with
// Gaussian noise of sigma_mm; each stored point standing for `weight`.
void add_wall(pv::rim::RimProfile *p, double edge_mm, double per_mm, double rise, double sigma_mm,
              double weight, Rng &r) {
  const double lo = -8.0;
  const int n = int(per_mm * (edge_mm - lo));
  for (int i = 0; i < n; ++i) {
    const double z = lo + (edge_mm - lo) * r.uniform();
    const double keep = 1.0 / (1.0 + rise);  // the density at the top is 1 + rise
    const double up = z > edge_mm - 2.0 ? (z - (edge_mm - 2.0)) / 2.0 : 0.0;
    if (r.uniform() > keep * (1.0 + rise * up)) continue;
    p->add(z + sigma_mm * r.gauss(), weight);
  }
}

// The order statistic the sector tops use: the third-highest point.
double third_highest(double edge_mm, double per_mm, double sigma_mm, Rng &r) {
  double top[3] = {-1e9, -1e9, -1e9};
  const int n = int(per_mm * 8.0);
  for (int i = 0; i < n; ++i) {
    double z = edge_mm - 8.0 * r.uniform() + sigma_mm * r.gauss();
    for (double &t : top)
      if (z > t) std::swap(z, t);
  }
  return top[2];
}

void a_top_edge_reads_the_same_long_or_short(void **) {
  // One pass: 600 points per mm of height, each stored. Twenty-five passes:
  // 15,000 per mm, thinned to one in eight. The plane through the third-
  // highest points rises with the count; the profile's edge does not.
  const double edge = -0.25, sigma = 0.1;
  Rng r{11};
  pv::rim::RimProfile once, long_scan;
  add_wall(&once, edge, 600, 0.1, sigma, 1.0, r);
  add_wall(&long_scan, edge, 15000.0 / 8.0, 0.1, sigma, 8.0, r);
  const double a = pv::rim::rim_offset_mm(once), b = pv::rim::rim_offset_mm(long_scan);
  // Within 0.05 mm (0.06 % of a 1 L pit, 150 mm across): the rise under
  // the edge, read over the 0.8 mm band below it, costs some hundredths.
  assert_true(std::fabs(a - edge) < 0.05);
  assert_true(std::fabs(b - edge) < 0.05);
  assert_true(std::fabs(a - b) < 0.04);
  // What the order statistic does with the same walls (independent draws).
  const double t1 = third_highest(edge, 600, sigma, r), t25 = third_highest(edge, 15000, sigma, r);
  assert_true(t25 - t1 > 0.05);
}

void a_lip_reads_at_its_surface(void **) {
  // A 6 mm lip on a 2 mm wall at the lid's height 0.3 mm under the plane,
  // and strays 0.5-2 mm over it (multipath: what held the sector tops up).
  const double lip = -0.3, sigma = 0.08;
  Rng r{12};
  pv::rim::RimProfile p;
  add_wall(&p, lip, 400, 0.0, sigma, 4.0, r);
  for (int i = 0; i < 6000; ++i) p.add(lip + sigma * r.gauss(), 4.0);
  for (int i = 0; i < 40; ++i) p.add(lip + 0.5 + 1.5 * r.uniform(), 1.0);
  assert_true(std::fabs(pv::rim::rim_offset_mm(p) - lip) < 0.02);
}

void too_few_points_under_the_top_keep_the_plane(void **) {
  Rng r{13};
  pv::rim::RimProfile p;
  add_wall(&p, -0.25, 15, 0.0, 0.1, 1.0, r);  // 45 points in the 3 mm band
  assert_true(pv::rim::rim_offset_mm(p) == 0.0);
}

void an_edge_far_from_the_plane_keeps_the_plane(void **) {
  // The plane 2 mm over the wall's edge: not a reading of the same top.
  Rng r{14};
  pv::rim::RimProfile p;
  add_wall(&p, -2.0, 600, 0.0, 0.1, 1.0, r);
  assert_true(pv::rim::rim_offset_mm(p) == 0.0);
}

void no_points_no_offset(void **) {
  const pv::rim::RimProfile p;
  assert_true(pv::rim::rim_offset_mm(p) == 0.0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(a_top_edge_reads_the_same_long_or_short),
      cmocka_unit_test(a_lip_reads_at_its_surface),
      cmocka_unit_test(too_few_points_under_the_top_keep_the_plane),
      cmocka_unit_test(an_edge_far_from_the_plane_keeps_the_plane),
      cmocka_unit_test(no_points_no_offset),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
