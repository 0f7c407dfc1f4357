// A scan that holds the pit twice, registered a few mm apart: a handheld
// scanner whose tracking slipped and which went on scanning from the wrong
// pose. The model takes the outer wall and the lower floor of the two
// copies, so without a check such scans read +0.3 to +3.1 % with PV_OK and
// an interval of about 0.25 % (docs/reliability.md, "Doubled scans"). The
// second surface behind the first refuses them: PV_ERR_NOT_A_PIT with
// PV_PIT_CHECK_DOUBLED_WALL (copies apart across the wall) or
// PV_PIT_CHECK_DOUBLED_FLOOR (apart along the axis). The same scan sent
// once measures within its interval. Copies closer than the band leave
// nothing behind it; they read up to +/-0.6 % with PV_OK unless the band's
// spread is part of the wall check, as it is.
#include <cmath>
#include <vector>

#include "pitvol/pitvol.h"
#include "session_support.h"
#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::sim::Family;

struct Scan {
  std::vector<pv_point_t> points;
  double exact_cm3;
};

// As `pitvol-sim scan --family F [--no-ground] --seed S [--noise MM]`
// makes it.
Scan simulate(Family family, bool ground, uint64_t seed, double noise_mm = pv::sim::ScanParams{}.noise_mm) {
  const pv::sim::Pit pit = pv::sim::make_pit(family, ground, seed);
  pv::sim::ScanParams sp;
  sp.seed = seed;
  sp.noise_mm = noise_mm;
  pv::sim::HandheldScan scan(pit, sp);
  Scan out{{}, pit.volume_mm3 / 1000.0};
  pv::sim::Frame f;
  while (scan.next(&f)) out.points.insert(out.points.end(), f.points.begin(), f.points.end());
  return out;
}

// The scan, then (if doubled) the scan again shifted by (dx, dy, dz) mm in
// the scanner's frame, in frames of 4096 points.
pv_status_t measure(const Scan &s, bool doubled, float dx, float dy, float dz, pv_result_t *r) {
  TestSession session;
  assert_int_equal(session.push_all(s.points, 4096), PV_OK);
  if (doubled) {
    std::vector<pv_point_t> copy = s.points;
    for (pv_point_t &p : copy) p = pv_point_t{p.x_mm + dx, p.y_mm + dy, p.z_mm + dz};
    assert_int_equal(session.push_all(copy, 4096), PV_OK);
  }
  return pv_session_finish(session.s, r);
}

void expect_doubled(Family family, bool ground, uint64_t seed, float dx, float dy, float dz,
                    pv_pit_check_t want) {
  const Scan s = simulate(family, ground, seed);
  const char *fam = pv::sim::family_name(family);
  pv_result_t once{};
  const pv_status_t st1 = measure(s, false, 0, 0, 0, &once);
  if (st1 != PV_OK) fail_msg("%s seed %llu once: %s", fam, (unsigned long long)seed, pv_status_name(st1));
  if (!(std::fabs(once.volume_cm3 - s.exact_cm3) <= once.interval_cm3)) {
    fail_msg("%s once: %.1f +/- %.1f cm3, exact %.1f", fam, once.volume_cm3, once.interval_cm3, s.exact_cm3);
  }
  pv_result_t twice{};
  const pv_status_t st2 = measure(s, true, dx, dy, dz, &twice);
  if (st2 == PV_OK) {
    fail_msg("%s doubled (%.1f, %.1f, %.1f) mm measured %.1f +/- %.1f cm3 (exact %.1f, %+.2f %%)", fam, double(dx),
             double(dy), double(dz), twice.volume_cm3, twice.interval_cm3, s.exact_cm3,
             100.0 * (twice.volume_cm3 - s.exact_cm3) / s.exact_cm3);
  }
  if (st2 != PV_ERR_NOT_A_PIT || twice.failed_check != uint32_t(want)) {
    fail_msg("%s doubled: %s %s (%g against %g), expected %s", fam, pv_status_name(st2),
             pv_pit_check_name(twice.failed_check), twice.check_value, twice.check_limit, pv_pit_check_name(want));
  }
  assert_true(twice.check_value > twice.check_limit);
  assert_true(twice.volume_cm3 == 0);
}

// Across the wall: 3 mm sideways (before the checks: 10818.5 +/- 28.9 cm3,
// exact 10675.6, +1.34 %), and 2.5 mm (+0.62 % +/- 0.27 %).
void cylinder_doubled_sideways(void **) {
  expect_doubled(Family::Cylinder, true, 1, 3.0f, 0.0f, 0.0f, PV_PIT_CHECK_DOUBLED_WALL);
}
void tapered_doubled_sideways(void **) {
  expect_doubled(Family::Tapered, true, 3, 0.0f, -2.5f, 0.5f, PV_PIT_CHECK_DOUBLED_WALL);
}
// Along the axis: the floor twice, 2 mm apart; the wall hardly moves
// (+0.64 % +/- 0.24 % before).
void tapered_doubled_along_the_axis(void **) {
  expect_doubled(Family::Tapered, false, 2, 0.0f, 0.2f, -2.0f, PV_PIT_CHECK_DOUBLED_FLOOR);
}

// Closer than the wall's band (1.5 mm): both copies inside it, so nothing
// behind it; the band's points spread about the bin's plane instead.
// Before that check: +0.57 % +/- 0.43 % (outside), and +0.06 % +/- 0.21 %.
void shallow_wide_doubled_within_the_band(void **) {
  expect_doubled(Family::ShallowWide, true, 1, 1.0f, 0.5f, 1.0f, PV_PIT_CHECK_DOUBLED_WALL);
}
void bowl_doubled_within_the_band(void **) {
  expect_doubled(Family::Bowl, false, 2, 0.0f, 1.0f, 0.3f, PV_PIT_CHECK_DOUBLED_WALL);
}

// A rounded bowl has no level floor: a 2 mm floor cell on its sloping
// bottom spans more height than the band, and the rest of its own surface
// fell in the ghost window. Scanned once with the sweeps' largest noise
// (0.2 mm), 3.2 % of the floor's points lay there and the bowl was refused
// as doubled (limit 3 %; tuning sweeps: rounded bowls 3.1-3.5 %, refused);
// over the level cells alone 0.40 %. It must measure within its interval.
void rounded_bowl_once_has_one_floor(void **) {
  const Scan s = simulate(Family::RoundedBowl, true, 1, 0.2);
  pv_result_t once{};
  const pv_status_t st = measure(s, false, 0, 0, 0, &once);
  if (st != PV_OK) {
    fail_msg("rounded bowl once: %s %s (%g against %g)", pv_status_name(st), pv_pit_check_name(once.failed_check),
             once.check_value, once.check_limit);
  }
  if (!(std::fabs(once.volume_cm3 - s.exact_cm3) <= once.interval_cm3)) {
    fail_msg("rounded bowl once: %.1f +/- %.1f cm3, exact %.1f", once.volume_cm3, once.interval_cm3, s.exact_cm3);
  }
}

// Its copy 2.5 mm higher (a slip along the axis) still doubles the level
// cells at the bottom of the bowl: refused.
void rounded_bowl_doubled_along_the_axis(void **) {
  expect_doubled(Family::RoundedBowl, true, 1, 0.0f, 0.0f, 2.5f, PV_PIT_CHECK_DOUBLED_FLOOR);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(cylinder_doubled_sideways),
      cmocka_unit_test(tapered_doubled_sideways),
      cmocka_unit_test(tapered_doubled_along_the_axis),
      cmocka_unit_test(shallow_wide_doubled_within_the_band),
      cmocka_unit_test(bowl_doubled_within_the_band),
      cmocka_unit_test(rounded_bowl_once_has_one_floor),
      cmocka_unit_test(rounded_bowl_doubled_along_the_axis),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
