// The tests' deterministic generator: splitmix64 + Box-Muller. The same
// draws on every platform and compiler, so a test's synthetic geometry is
// the same bits everywhere.
#ifndef PV_TESTS_TEST_RNG_H
#define PV_TESTS_TEST_RNG_H

#include <cmath>
#include <cstdint>

#include "pitvol/splitmix64.h"

namespace pv::test {

constexpr double kPi = 3.14159265358979323846;

struct Rng {
  uint64_t s;
  uint64_t next() { return pv_splitmix64_next(&s); }
  // Uniform in (0, 1): never 0, so log() in gauss() stays finite.
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }
  double gauss() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }
};

}  // namespace pv::test

#endif
