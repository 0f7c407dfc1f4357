// The polar angle of a point, the arc cosine, the sine and the cosine,
// without libm.
//
// Why not std::atan2: libm's atan2 is not guaranteed to round alike on
// x86-64, aarch64 and newlib (the M7): the same-bits tests only showed it
// did on the scans they replay. The rim plane's sectors, the per-layer
// methods' clustering and polar fit use this one (the surface model bins
// with surface/angle_bins.h instead). It
// uses + - * / and comparisons only, which IEEE 754 rounds the same way on
// every target (the core is built with -ffp-contract=off), so its bits are
// the same everywhere by construction.
//
// Method: the Cephes library's atan (S. L. Moshier, atan.c, public
// constants): the ratio of the smaller to the larger |coordinate| in
// [0, 1], reduced to |x| <= 0.66 by atan(x) = pi/4 + atan((x-1)/(x+1)), a
// 4/5 rational function there; then the octant and quadrant by symmetry.
// Measured against glibc's atan2 on 10^7 random points: within 2 ulp of
// 2 pi (tests/unit/surface/test_angle_bins.cpp).
#ifndef PV_COMMON_ANGLE_H
#define PV_COMMON_ANGLE_H

#include <cmath>

namespace pv {

constexpr double kTwoPi = 6.28318530717958647692;

// atan(n) for n in [0, 1]. Selects, not branches: n is random per point,
// and a mispredicted branch costs more than computing both sides.
inline double atan_unit(double n) {
  constexpr double kPiOver4 = 0.78539816339744830962;
  constexpr double kMoreBits = 6.123233995736765886130e-17;  // pi/4 - double(pi/4)
  const bool reduce = n > 0.66;
  const double base = reduce ? kPiOver4 : 0.0;
  const double more = reduce ? 0.5 * kMoreBits : 0.0;
  const double num = reduce ? n - 1.0 : n, den = reduce ? n + 1.0 : 1.0;
  n = num / den;
  const double z = n * n;
  const double p =
      (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z -
        7.500855792314704667340e1) * z - 1.228866684490136173410e2) * z -
      6.485021904942025371773e1;
  const double q =
      ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z +
        4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z +
      1.945506571482613964425e2;
  return base + ((n * (z * p / q) + n) + more);
}

// Angle of (x, y) in [0, 2 pi): atan2(y, x), plus 2 pi where negative.
// (0, 0) gives 0.
inline double angle_2pi(double y, double x) {
  constexpr double kPiOver2 = 1.57079632679489661923;
  constexpr double kPi = 3.14159265358979323846;
  const double ax = std::fabs(x), ay = std::fabs(y);
  const bool steep = ay > ax;
  const double num = steep ? ax : ay, den = steep ? ay : ax;
  if (!(den > 0.0)) return 0.0;  // the origin
  const double t = atan_unit(num / den);
  double a = steep ? kPiOver2 - t : t;
  a = x < 0.0 ? kPi - a : a;
  return y < 0.0 ? kTwoPi - a : a;
}

// Which of n equal sectors from angle 0 the point (x, y) lies in, 0 to n - 1
// (an angle rounded up to 2 pi stays in the last).
inline int sector_of(double y, double x, int n) {
  const int k = int(angle_2pi(y, x) * (n / kTwoPi));
  return k < n - 1 ? k : n - 1;
}

// atan2(y, x) in (-pi, pi] (the range the crescent's angle window is
// given in, core/clustering): angle_2pi, less 2 pi above pi. (0, 0) gives 0;
// y = -0 with x < 0 gives pi, not atan2's -pi.
inline double angle_pi(double y, double x) {
  constexpr double kPi = 3.14159265358979323846;
  const double a = angle_2pi(y, x);
  return a > kPi ? a - kTwoPi : a;
}

// sin a and cos a for a in [0, 2 pi], to about 1 ulp (angle.cpp: a Taylor
// series, + - * / only). For the surface model's bin edges, the polar
// fit's basis and the area fit's Chebyshev nodes.
void sin_cos(double a, double *s, double *c);

// acos(c) in [0, pi] for c in [-1, 1], without libm: the angle of
// (c, sin), the sine as sqrt((1 - c)(1 + c)) (1 - c is exact near c = 1,
// where 1 - c * c would cancel: small angles keep their relative accuracy).
// For the levelling's tilt and its convergence test (levelling.cpp).
inline double angle_of_cos(double c) {
  c = c < -1.0 ? -1.0 : (c > 1.0 ? 1.0 : c);
  return angle_2pi(std::sqrt((1.0 - c) * (1.0 + c)), c);
}

}  // namespace pv

#endif
