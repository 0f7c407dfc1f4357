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

void AngleBins::init(uint32_t n) {
  if (n > kMaxBins) n = kMaxBins;
  if (n == 0) n = 1;
  n_ = n;
  const double step = 2 * kPi / n;
  bound_[0] = 0.0;
  for (uint32_t t = 1; t < n; ++t) {
    double s, c;
    sin_cos(t * step, &s, &c);
    bound_[t] = diamond(c, s);
  }
  bound_[n] = HUGE_VAL;  // d may round to 4: it stays in the last bin
  for (uint32_t t = 0; t < n; ++t) sin_cos((t + 0.5) * step, &cs_[t], &cc_[t]);
  // start_[j]: the bin of the lowest diamond angle of coarse cell j.
  uint32_t t = 0;
  for (uint32_t j = 0; j < kCoarse; ++j) {
    const double d = double(j) / kCoarsePerUnit;
    while (t + 1 < n && d >= bound_[t + 1]) ++t;
    start_[j] = uint16_t(t);
  }
}

}  // namespace pv::surface
