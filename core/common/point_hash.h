// A hash of a point's exact coordinate bits.
//
// Why: thinning and sampling decisions keyed on the point itself (not on its
// arrival position) make the core independent of the order points arrive in:
// the same set of points gives the same sample and the same thinned bins.
#ifndef PV_COMMON_POINT_HASH_H
#define PV_COMMON_POINT_HASH_H

#include <cstdint>
#include <cstring>

#include "common/geometry.h"
#include "pitvol/splitmix64.h"

namespace pv {

inline uint64_t mix64(uint64_t v) { return pv_splitmix64_mix(v); }

inline uint64_t point_hash(const P3 &p) {
  uint32_t b[3];
  std::memcpy(b, &p, sizeof b);
  // +0.0 and -0.0 are the same point.
  for (uint32_t &w : b) {
    if (w == 0x80000000u) w = 0;
  }
  uint64_t h = mix64((uint64_t(b[0]) << 32) ^ b[1]);
  return mix64(h ^ (uint64_t(b[2]) * 0x9e3779b97f4a7c15ull));
}

// Deterministic PRNG for RANSAC: same seed, same draws, on every platform.
struct SplitMix64 {
  uint64_t state;
  uint64_t next() { return pv_splitmix64_next(&state); }
  // Uniform integer in [0, n), n > 0 (modulo bias negligible for n << 2^64).
  uint32_t below(uint32_t n) { return uint32_t(next() % n); }
};

}  // namespace pv

#endif
