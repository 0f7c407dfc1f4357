// splitmix64: the simulator's random draws, the same on every platform and
// compiler (integer arithmetic only).
#ifndef PV_SIM_SPLITMIX_H
#define PV_SIM_SPLITMIX_H

#include <cstdint>

namespace pv::sim {

inline uint64_t splitmix64(uint64_t *state) {
  uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace pv::sim

#endif
