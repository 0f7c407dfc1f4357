// The rim as a plane through the sector tops (method surface's lid when the
// scan has no ground ring): known tilted planes, unscanned tops, strays.
#include <array>
#include <cmath>
#include <vector>

#include "rim/rim_plane.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::rim::kRimSectors;
using pv::test::kPi;
using pv::test::Rng;

constexpr double kCx = 12.0, kCy = -7.0, kRadius = 110.0;

struct Lid {
  double z0, bx, by;  // z = z0 + bx x + by y
  double at(double x, double y) const { return z0 + bx * x + by * y; }
};

// A pit wall of radius 110 around (12, -7) up to the lid: in each sector
// the top point on the lid, two more 1 and 2 mm below it, then wall points
// further down. Sectors in `low` were not scanned to the top: their points
// stop `drop_mm` below the lid.
pv::rim::SectorTops wall_under(const Lid &lid, uint64_t low, double drop_mm, Rng &r) {
  pv::rim::SectorTops t;
  t.clear(kCx, kCy);
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    const double th = (s + 0.2 + 0.6 * r.uniform()) * 2 * kPi / kRimSectors;
    const double x = kCx + kRadius * std::cos(th), y = kCy + kRadius * std::sin(th);
    const double top = lid.at(x, y) - ((low >> s) & 1 ? drop_mm : 0.0);
    for (int k = 0; k < 12; ++k) t.offer(x, y, top - (k < 3 ? k : 5.0 * k));
  }
  return t;
}

// The lid's normal and offset as fit_rim_plane reports them.
void expect_plane(const pv::rim::RimPlane &p, const Lid &lid) {
  const Eigen::Vector3d n = Eigen::Vector3d(-lid.bx, -lid.by, 1.0).normalized();
  assert_true((p.normal - n).norm() < 1e-6);
  assert_true(std::fabs(p.d - n.z() * lid.z0) < 1e-3);  // mm; float storage
}

void finds_a_tilted_rim(void **) {
  Rng r{7};
  const Lid lid{283.0, 0.05, -0.03};  // 3.3 deg
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(wall_under(lid, 0, 0, r));
  assert_true(p.found);
  assert_int_equal(p.sectors, kRimSectors);
  assert_true(p.rms_mm < 1e-4);
  expect_plane(p, lid);
}

void unscanned_tops_do_not_tilt_it(void **) {
  // Eight sectors' highest points are wall 20 mm down: the consensus leaves
  // them out, and the plane is still the lid through the other 28.
  Rng r{8};
  const Lid lid{250.0, -0.02, 0.04};
  uint64_t low = 0;
  for (const int s : {1, 2, 3, 10, 17, 25, 26, 33}) low |= uint64_t{1} << s;
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(wall_under(lid, low, 20.0, r));
  assert_true(p.found);
  assert_int_equal(p.sectors, kRimSectors - 8);
  expect_plane(p, lid);
}

void a_stray_above_the_rim_is_not_a_top(void **) {
  // A lone point 40 mm above the lid in every sector (no two more within
  // 3 mm below it): the sector top is the lid's point under it.
  Rng r{9};
  const Lid lid{300.0, 0.01, 0.01};
  pv::rim::SectorTops t = wall_under(lid, 0, 0, r);
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    const double th = (s + 0.5) * 2 * kPi / kRimSectors;
    const double x = kCx + 60 * std::cos(th), y = kCy + 60 * std::sin(th);
    t.offer(x, y, lid.at(x, y) + 40.0);
  }
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(t);
  assert_true(p.found);
  assert_int_equal(p.sectors, kRimSectors);
  expect_plane(p, lid);
}

// A vessel's lip scanned long: its dense flat ring fills its layers, which
// thin (level 4), while multipath floating 0.6-1.8 mm over it keeps the
// layers above unthinned (level 0). Three such points within 3 mm, over
// half the round, were the tops there: the plane tilted and raised (fresh
// seed 1309 #282, +2.7 % from its single pass). Points standing for 16
// times fewer than the lip's are not its top.
void multipath_over_a_thinned_lip_is_not_a_top(void **) {
  Rng r{12};
  const Lid lid{250.0, 0.004, -0.002};
  pv::rim::SectorTops t;
  t.clear(kCx, kCy);
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    const double th = (s + 0.2 + 0.6 * r.uniform()) * 2 * kPi / kRimSectors;
    const double x = kCx + kRadius * std::cos(th), y = kCy + kRadius * std::sin(th);
    for (int k = 0; k < 8; ++k) t.offer(x, y, lid.at(x, y) - 0.01 * k, 4);
    if (s < kRimSectors / 2) {
      for (int k = 1; k <= 3; ++k) t.offer(x, y, lid.at(x, y) + 0.6 * k, 0);
    }
  }
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(t);
  assert_true(p.found);
  assert_int_equal(p.sectors, kRimSectors);
  expect_plane(p, lid);
}

// Eight lone strays above the lid in every sector fill all its slots (a
// long or a large scan): no sector has a top, and no rim. dig() lowers each
// such sector's ceiling and the points offered again give the lid's tops,
// while a sector with a top keeps it and takes no point twice.
void eight_strays_per_sector_are_dug_through(void **) {
  Rng r{11};
  const Lid lid{760.0, 0.02, -0.01};
  std::vector<std::array<double, 3>> pts;
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    const double th = (s + 0.2 + 0.6 * r.uniform()) * 2 * kPi / kRimSectors;
    const double x = kCx + kRadius * std::cos(th), y = kCy + kRadius * std::sin(th);
    for (int k = 0; k < 12; ++k) pts.push_back({x, y, lid.at(x, y) - (k < 3 ? k : 5.0 * k)});
    if (s == 0) continue;  // sector 0: its top stands
    for (int q = 0; q < 8; ++q) {
      const double ts = (s + 0.5) * 2 * kPi / kRimSectors, rs = 200.0 + 30.0 * q;
      pts.push_back({kCx + rs * std::cos(ts), kCy + rs * std::sin(ts), lid.at(x, y) + 10.0 + 7.0 * q});
    }
  }
  pv::rim::SectorTops t;
  t.clear(kCx, kCy);
  for (const auto &p : pts) t.offer(p[0], p[1], p[2]);
  assert_false(pv::rim::fit_rim_plane(t).found);
  int rounds = 0;
  while (rounds < pv::rim::kRimDigRounds && t.dig()) {
    for (const auto &p : pts) t.offer(p[0], p[1], p[2]);
    ++rounds;
  }
  assert_true(rounds >= 1);
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(t);
  assert_true(p.found);
  assert_int_equal(p.sectors, kRimSectors);
  expect_plane(p, lid);
  assert_true(t.z[0][0] > t.z[0][1]);  // sector 0 not offered twice
}

void too_few_sectors_on_a_plane(void **) {
  // Every other sector's top 20 mm down: 18 tops on either plane, under 24:
  // not found, but partial (a last resort for the caller).
  Rng r{10};
  const pv::rim::RimPlane p =
      pv::rim::fit_rim_plane(wall_under(Lid{283.0, 0, 0}, 0x555555555ull, 20.0, r));
  assert_false(p.found);
  assert_true(p.partial);
  assert_int_equal(p.sectors, 18);
  // 17 sectors scanned, all on the lid: nothing.
  pv::rim::SectorTops t;
  t.clear(kCx, kCy);
  for (uint32_t s = 0; s < 17; ++s) {
    const double th = (2 * s + 0.5) * 2 * kPi / kRimSectors;
    const double x = kCx + kRadius * std::cos(th), y = kCy + kRadius * std::sin(th);
    for (int k = 0; k < 12; ++k) t.offer(x, y, 283.0 - (k < 3 ? k : 5.0 * k));
  }
  const pv::rim::RimPlane q = pv::rim::fit_rim_plane(t);
  assert_false(q.found);
  assert_false(q.partial);
}

// The lid seen in the first `on` sectors; the others' tops drop[s] down
// the wall (each its own depth: a wall whose top the scanner did not see).
pv::rim::SectorTops lid_in_some(uint32_t on, double lid, const std::array<double, kRimSectors> &drop) {
  pv::rim::SectorTops t;
  t.clear(kCx, kCy);
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    const double th = (s + 0.5) * 2 * kPi / kRimSectors;
    const double x = kCx + kRadius * std::cos(th), y = kCy + kRadius * std::sin(th);
    const double top = lid - (s < on ? 0.0 : drop[s]);
    for (int k = 0; k < 12; ++k) t.offer(x, y, top - (k < 3 ? k : 5.0 * k));
  }
  return t;
}

void the_highest_edge_seen_in_a_third_of_the_sectors(void **) {
  // 14 sectors show the lid, the other 22 their wall 12-90 mm down at
  // random (a deep pit without surround scanned from one side; tuning seed
  // 5 #047 showed 16 of 36): the highest edge, nowhere exceeded: partial.
  Rng r{14};
  std::array<double, kRimSectors> drop{};
  for (double &d : drop) d = 12.0 + 78.0 * r.uniform();
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(lid_in_some(14, 283.0, drop));
  assert_false(p.found);
  assert_true(p.partial);
  assert_int_equal(p.sectors, 14);
  assert_true(std::fabs(p.d - 283.0) < 0.5);
  // One of the others' top 10 mm above the lid instead (three points
  // within 3 mm: not a stray): the 14 are not the top; nothing.
  std::array<double, kRimSectors> one_up = drop;
  one_up[20] = -10.0;
  const pv::rim::RimPlane q = pv::rim::fit_rim_plane(lid_in_some(14, 283.0, one_up));
  assert_false(q.found);
  assert_false(q.partial);
  // 11 on the lid: too few, however clean.
  assert_false(pv::rim::fit_rim_plane(lid_in_some(11, 283.0, drop)).partial);
}

void a_rim_12_degrees_off_is_found(void **) {
  // The floor-plane levelling of a bowl scanned from one side can be 12 deg
  // off (pitvol-sim scan --family bowl --no-ground --arc 180 --seed 5);
  // the rim plane must still level it.
  Rng r{12};
  const Lid lid{270.0, 0.17, -0.12};  // 11.8 deg
  const pv::rim::RimPlane p = pv::rim::fit_rim_plane(wall_under(lid, 0, 0, r));
  assert_true(p.found);
  expect_plane(p, lid);
}

void too_steep_is_not_a_rim(void **) {
  // 0.38 mm/mm is 20.8 deg, beyond the 20 deg a rim plane may correct
  // unless 28 or more sectors lie on it (a rounded bowl's floor fit lay
  // 33-49 deg off): with 27 it is neither found nor partial.
  Rng r{11};
  const pv::rim::RimPlane few =
      pv::rim::fit_rim_plane(wall_under(Lid{283.0, 0.38, 0}, 0x1FFull, 20.0, r));
  assert_false(few.found);
  assert_false(few.partial);
  const pv::rim::RimPlane steep =
      pv::rim::fit_rim_plane(wall_under(Lid{283.0, 0.38, 0}, 0xFFull, 20.0, r));
  assert_true(steep.found);
  assert_true(steep.steep);
  const pv::rim::RimPlane level = pv::rim::fit_rim_plane(wall_under(Lid{283.0, 0.35, 0}, 0, 0, r));
  assert_true(level.found);
  assert_false(level.steep);
  // 1.8 mm/mm is 60.9 deg: beyond any start frame's correction.
  assert_false(pv::rim::fit_rim_plane(wall_under(Lid{283.0, 1.8, 0}, 0, 0, r)).found);
}

void an_empty_scan_has_no_rim(void **) {
  pv::rim::SectorTops t;
  t.clear(0, 0);
  assert_false(pv::rim::fit_rim_plane(t).found);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(finds_a_tilted_rim),
      cmocka_unit_test(eight_strays_per_sector_are_dug_through),
      cmocka_unit_test(unscanned_tops_do_not_tilt_it),
      cmocka_unit_test(a_stray_above_the_rim_is_not_a_top),
      cmocka_unit_test(multipath_over_a_thinned_lip_is_not_a_top),
      cmocka_unit_test(too_few_sectors_on_a_plane),
      cmocka_unit_test(the_highest_edge_seen_in_a_third_of_the_sectors),
      cmocka_unit_test(a_rim_12_degrees_off_is_found),
      cmocka_unit_test(too_steep_is_not_a_rim),
      cmocka_unit_test(an_empty_scan_has_no_rim),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
