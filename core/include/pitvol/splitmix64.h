/*
 * splitmix64 (Steele, Lea, Flood 2014): the one generator behind every
 * deterministic draw in pitvol (the core's RANSAC and point hash, the
 * simulator, the synthetic pit, the emulated scanner, the tests and fuzz
 * harnesses). Integer arithmetic only: the same draws on every target and
 * compiler, so a seed names the same scan everywhere.
 */
#ifndef PITVOL_SPLITMIX64_H
#define PITVOL_SPLITMIX64_H

#include <stdint.h>

/* The output function: a bijective mix of 64 bits (also a hash finaliser). */
static inline uint64_t pv_splitmix64_mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/* The next draw: advances *state by the golden-ratio increment. */
static inline uint64_t pv_splitmix64_next(uint64_t *state) {
  *state += 0x9E3779B97F4A7C15ull;
  return pv_splitmix64_mix(*state);
}

/* A draw as a double uniform in [0, 1): its top 53 bits. */
static inline double pv_splitmix64_unit(uint64_t *state) {
  return (double)(pv_splitmix64_next(state) >> 11) * (1.0 / 9007199254740992.0);
}

#endif /* PITVOL_SPLITMIX64_H */
