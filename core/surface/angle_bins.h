// Equal angle bins around a centre, found without an arc tangent.
//
// Why: the surface model bins every stored point by its angle around the
// pit's axis; an atan2 per point was the largest single cost of finish()
// (docs/benchmarks.md). The bin needs only the order of angles, which the
// "diamond angle" D(x, y) in [0, 4) keeps (one division, monotone in the
// angle): a point is in bin t when bound[t] <= D < bound[t + 1], with bound
// the diamond angles of the bins' edges. A coarse table of D gives the bin
// to start from, so a lookup is a division and one or two comparisons.
//
// Same bits everywhere: the edges' directions come from sin_cos() below
// (a Taylor series: + - * / only), D from + and /, so no libm function can
// round differently on another target (the core is built with
// -ffp-contract=off). Points exactly on an edge go to the upper bin; a bin
// differs from floor(atan2 * T / 2 pi) only within rounding of an edge.
#ifndef PV_SURFACE_ANGLE_BINS_H
#define PV_SURFACE_ANGLE_BINS_H

#include <cstdint>

namespace pv::surface {

// sin and cos of a in [0, 2 pi], to about 1 ulp.
void sin_cos(double a, double *s, double *c);

// Diamond angle of (x, y): 0 along +x, 1 along +y, 2 along -x, 3 along -y,
// in [0, 4]; (0, 0) gives 0. Selects, not branches: the quadrant of a point
// is random from one point to the next.
inline double diamond(double x, double y) {
  const double ax = x < 0 ? -x : x, ay = y < 0 ? -y : y;
  const double sum = ax + ay;
  const double r = ay / (sum > 0.0 ? sum : 1.0);  // [0, 1]
  const int left = x < 0, down = y < 0;
  // Quadrants +x+y, -x+y, -x-y, +x-y: r, 2 - r, 2 + r, 4 - r (exact: r * +-1).
  const double base = double(2 * left + 4 * (down & (1 - left)));
  return base + r * double(1 - 2 * (left ^ down));
}

class AngleBins {
 public:
  static constexpr uint32_t kMaxBins = 360;

  // n equal bins from angle 0, n <= kMaxBins.
  void init(uint32_t n);
  uint32_t bins() const { return n_; }

  uint32_t bin(double dx, double dy) const {
    const double d = diamond(dx, dy);
    auto j = uint32_t(d * kCoarsePerUnit);
    if (j >= kCoarse) j = kCoarse - 1;
    // A coarse cell (1/256) is narrower than any bin (at least 1/180 of a
    // turn at kMaxBins = 360), so it meets at most two bins: one step.
    uint32_t t = start_[j];
    t += d >= bound_[t + 1] ? 1 : 0;
    return t;
  }

  // Direction of the centre of bin t.
  double centre_cos(uint32_t t) const { return cc_[t]; }
  double centre_sin(uint32_t t) const { return cs_[t]; }

  // Angle of (dx, dy) from the centre of bin t, radians, for a point of
  // that bin (|angle| about pi / n at most): the arc tangent of a small
  // ratio, by its series.
  double from_centre(uint32_t t, double dx, double dy) const {
    const double u = dx * cc_[t] + dy * cs_[t];
    const double v = dy * cc_[t] - dx * cs_[t];
    if (!(u > 0.0)) return 0.0;
    const double q = v / u;
    const double z = q * q;
    // atan q = q (1 - z/3 + z^2/5 - z^3/7 + z^4/9 - ...): |q| <= tan(pi/n),
    // for n >= 36 below 0.088, so the next term is under 3e-13 of q.
    return q * (1.0 - z * (1.0 / 3 - z * (1.0 / 5 - z * (1.0 / 7 - z * (1.0 / 9 - z / 11)))));
  }

 private:
  static constexpr uint32_t kCoarsePerUnit = 256;  // a bin of 1 deg or more spans several
  static constexpr uint32_t kCoarse = 4 * kCoarsePerUnit;
  uint32_t n_ = 0;
  double bound_[kMaxBins + 1];  // bound_[n] is +infinity
  double cc_[kMaxBins], cs_[kMaxBins];
  uint16_t start_[kCoarse];
};

}  // namespace pv::surface

#endif
