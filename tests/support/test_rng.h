// The tests' deterministic generator: splitmix64 + Box-Muller. The same
// draws on every platform and compiler, so a test's synthetic geometry is
// the same bits everywhere.
#ifndef PV_TESTS_TEST_RNG_H
#define PV_TESTS_TEST_RNG_H

#include <cmath>
#include <cstdint>

namespace pv::test {

constexpr double kPi = 3.14159265358979323846;

struct Rng {
  uint64_t s;
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in (0, 1): never 0, so log() in gauss() stays finite.
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }
  double gauss() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }
};

}  // namespace pv::test

#endif
