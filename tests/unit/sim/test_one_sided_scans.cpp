// Pits scanned from one side, through the simulator and the default method.
//
// Bowls. A bowl has no flat floor, so the floor-plane levelling that method surface
// starts from can be 12 deg off when the operator walks only part of the way
// round; the ground plane (or, without ground, the rim plane) must still
// level the scan, so both are looked for within 20 deg. Looked for within
// 10 deg only, the volume is taken under a tilted lid: +22.5 % (ground,
// 300 deg arc, seed 5) and +10.2 % (no ground, 180 deg, seed 5), with PV_OK
// and an interval of 1.5 and 0.3 %.
//
// A third of the way round. The wall below the operator is bridged from the
// seen wall beside it; where it hides an undercut the bridge lies inside it,
// and an interval from the same neighbours does not hold the truth
// (deep_narrow -2.08 % against +/-0.43 %, bulge -0.70 % against +/-0.48 %).
// So such wall's interval spans the radii seen at its height.
//
// The floor seen from one side. The flooded floor of a shallow wide pit
// scanned 300 deg round reached the foot of the wall, whose points above it
// look like a second floor: counted there, the doubled-scan check
// (test_doubled_scans) refuses it (0.106 of the floor's points above it
// against at most 0.03). So the check leaves the cells at the wall's foot
// out, as the volume does.
//
// Each case must measure within its interval of the exact volume.
#include <cstdio>

#include "sim_scan_check.h"  // last: it includes pv_cmocka.h

namespace {

struct Case {
  pv::sim::Family family;
  bool ground;
  double arc_deg;
  uint64_t seed;
};

// As `pitvol-sim scan --family F [--no-ground] --arc A --seed S` makes it.
void measures_within_its_interval(const Case &c) {
  pv::sim::ScanParams sp;
  sp.seed = c.seed;
  sp.path_arc_deg = c.arc_deg;
  char what[64];
  std::snprintf(what, sizeof what, "arc %.0f seed %llu", c.arc_deg, (unsigned long long)c.seed);
  expect_within_interval(c.family, c.ground, sp, what);
}

using pv::sim::Family;
void bowl_ground_ring_300_degrees(void **) { measures_within_its_interval({Family::Bowl, true, 300.0, 5}); }
void bowl_ground_ring_180_degrees(void **) { measures_within_its_interval({Family::Bowl, true, 180.0, 6}); }
void bowl_no_ground_180_degrees(void **) { measures_within_its_interval({Family::Bowl, false, 180.0, 5}); }
void deep_narrow_120_degrees(void **) { measures_within_its_interval({Family::DeepNarrow, true, 120.0, 3}); }
void bulge_120_degrees(void **) { measures_within_its_interval({Family::Bulge, true, 120.0, 2}); }
void shallow_wide_300_degrees(void **) { measures_within_its_interval({Family::ShallowWide, true, 300.0, 3}); }

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bowl_ground_ring_300_degrees),
      cmocka_unit_test(bowl_ground_ring_180_degrees),
      cmocka_unit_test(bowl_no_ground_180_degrees),
      cmocka_unit_test(deep_narrow_120_degrees),
      cmocka_unit_test(bulge_120_degrees),
      cmocka_unit_test(shallow_wide_300_degrees),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
