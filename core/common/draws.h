// Fixed-sequence draws for the rim stage's deterministic RANSAC (the ground
// plane, the support plane): the same scan gives the same plane on every
// target. An LCG with Knuth's MMIX constants, an index from its top 31 bits.
// Not splitmix64 (pitvol/splitmix64.h, the host tools' and tests' draws):
// the ground plane's draws came first, and other draws would move every
// volume levelled on a ground ring.
#ifndef PV_COMMON_DRAWS_H
#define PV_COMMON_DRAWS_H

#include <cstddef>
#include <cstdint>

namespace pv {

struct LcgDraws {
  uint64_t state;
  // An index in [0, m), m > 0.
  size_t next(size_t m) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return size_t((state >> 33) % m);
  }
};

}  // namespace pv

#endif
