#include "surface/angle_bins.h"

#include <cmath>

#include "common/angle.h"

namespace pv::surface {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

size_t AngleBins::bytes_for(uint32_t n) {
  if (n > kMaxBins) n = kMaxBins;
  if (n == 0) n = 1;
  const size_t doubles = size_t(n + 1) + 2 * size_t(n);
  return doubles * sizeof(double) + (4 * size_t(coarse_per_unit(n)) * sizeof(uint16_t) + 7) / 8 * 8;
}

void AngleBins::init(uint32_t n, void *memory) {
  if (n > kMaxBins) n = kMaxBins;
  if (n == 0) n = 1;
  n_ = n;
  per_unit_ = coarse_per_unit(n);
  auto *bound = static_cast<double *>(memory);
  double *cc = bound + n + 1, *cs = cc + n;
  auto *start = reinterpret_cast<uint16_t *>(cs + n);
  const double step = 2 * kPi / n;
  bound[0] = 0.0;
  for (uint32_t t = 1; t < n; ++t) {
    double s, c;
    sin_cos(t * step, &s, &c);
    bound[t] = diamond(c, s);
  }
  bound[n] = HUGE_VAL;  // d may round to 4: it stays in the last bin
  for (uint32_t t = 0; t < n; ++t) sin_cos((t + 0.5) * step, &cs[t], &cc[t]);
  // start[j]: the bin of the lowest diamond angle of coarse cell j.
  uint32_t t = 0;
  for (uint32_t j = 0; j < 4 * per_unit_; ++j) {
    const double d = double(j) / per_unit_;
    while (t + 1 < n && d >= bound[t + 1]) ++t;
    start[j] = uint16_t(t);
  }
  bound_ = bound;
  cc_ = cc;
  cs_ = cs;
  start_ = start;
}

}  // namespace pv::surface
