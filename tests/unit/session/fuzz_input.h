// A session harness's input file (a regression seed of fuzz/corpus/session)
// as points, for the unit tests that replay a finding as it was found.
#ifndef PV_TESTS_FUZZ_INPUT_H
#define PV_TESTS_FUZZ_INPUT_H

#include <cstdio>
#include <vector>

#include "fuzz_session_config.h"

// Empty if the file cannot be read or holds no seed: callers assert the
// point count they expect.
inline std::vector<pv_point_t> fuzz_input_points(const char *path) {
  std::FILE *f = std::fopen(path, "rb");
  if (f == nullptr) return {};
  std::vector<uint8_t> bytes;
  uint8_t buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + n);
  std::fclose(f);
  if (bytes.size() < 8) return {};
  uint64_t seed;
  return pv::fuzz::input_points(bytes.data(), bytes.size(), &seed);
}

#endif
