// Helpers shared by the session tests: a session in an aligned block
// (tests/support/test_session.h), and a synthetic scan as a vector.
#ifndef PV_TESTS_SESSION_SUPPORT_H
#define PV_TESTS_SESSION_SUPPORT_H

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "pitvol/pitvol.h"
#include "synth/synthetic_pit.h"
#include "test_session.h"

inline std::vector<pv_point_t> scan_points(const pv::synth::PitSpec &spec, size_t n) {
  pv::synth::PitScan scan(spec);
  std::vector<pv_point_t> v(n);
  for (pv_point_t &p : v) p = scan.next();
  return v;
}

inline double rel_err(double v, double truth) { return (v - truth) / truth; }

#endif
