// sin and cos without libm (common/angle.h): the same bits on every target.
#include "common/angle.h"

namespace pv {

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

}  // namespace pv
