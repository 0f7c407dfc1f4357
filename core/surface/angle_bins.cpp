#include "surface/angle_bins.h"

#include <cmath>

namespace pv::surface {

namespace {

constexpr double kPi = 3.14159265358979323846;

// sin x and cos x for x in [0, pi/4], Taylor series to the x^18 terms
// (the next are below 1e-19).
void sin_cos_octant(double x, double *s, double *c) {
  const double z = x * x;
  double ps = 0.0, pc = 0.0;
  // sin x = x (1 - z/(2*3) (1 - z/(4*5) (1 - ...)))
  for (int k = 17; k >= 3; k -= 2) ps = z / double((k - 1) * k) * (1.0 - ps);
  *s = x * (1.0 - ps);
  for (int k = 18; k >= 2; k -= 2) pc = z / double((k - 1) * k) * (1.0 - pc);
  *c = 1.0 - pc;
}

}  // namespace

void sin_cos(double a, double *s, double *c) {
  // Quadrant by comparison, then the octant by symmetry about pi/4.
  int q = 0;
  while (q < 3 && a > (q + 1) * (kPi / 2)) ++q;
  double r = a - q * (kPi / 2);
  if (r < 0) r = 0;
  double rs, rc;
  if (r > kPi / 4) {
    sin_cos_octant(kPi / 2 - r, &rc, &rs);
  } else {
    sin_cos_octant(r, &rs, &rc);
  }
  switch (q) {
    case 0: *s = rs; *c = rc; break;
    case 1: *s = rc; *c = -rs; break;
    case 2: *s = -rs; *c = -rc; break;
    default: *s = -rc; *c = rs; break;
  }
}

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
