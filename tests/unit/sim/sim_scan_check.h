// A simulator scan through the default method, checked against its pit's
// exact volume: PV_OK, and the volume within the result's interval. The
// pit and the scan are what `pitvol-sim scan --family F [--no-ground]
// --seed S ...` makes with sp (S = sp.seed); `what` names the case in a
// failure. It asserts with cmocka, so it includes pv_cmocka.h last: include
// it last, in place of pv_cmocka.h.
#ifndef PV_TESTS_SIM_SCAN_CHECK_H
#define PV_TESTS_SIM_SCAN_CHECK_H
#include <cmath>

#include "pitvol/pitvol.h"
#include "session_support.h"
#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

inline void expect_within_interval(pv::sim::Family family, bool ground, const pv::sim::ScanParams &sp,
                                   const char *what) {
  const pv::sim::Pit pit = pv::sim::make_pit(family, ground, sp.seed);
  pv::sim::HandheldScan scan(pit, sp);
  TestSession session;
  pv::sim::Frame f;
  while (scan.next(&f)) assert_int_equal(pv_session_push(session.s, f.points.data(), f.points.size()), PV_OK);
  pv_result_t r{};
  const pv_status_t st = pv_session_finish(session.s, &r);
  const double exact = pit.volume_mm3 / 1000.0;
  const char *fam = pv::sim::family_name(family);
  const char *gr = ground ? "ground" : "no ground";
  if (st != PV_OK) fail_msg("%s %s %s: %s", fam, gr, what, pv_status_name(st));
  if (!(std::fabs(r.volume_cm3 - exact) <= r.interval_cm3)) {
    fail_msg("%s %s %s: %.1f +/- %.1f cm3, exact %.1f (%+.2f %%)", fam, gr, what, r.volume_cm3, r.interval_cm3,
             exact, 100.0 * (r.volume_cm3 - exact) / exact);
  }
}

#endif  // PV_TESTS_SIM_SCAN_CHECK_H
