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
// Same bits everywhere: the edges' directions come from pv::sin_cos()
// (common/angle.h: a Taylor series, + - * / only), D from + and /, so no libm function can
// round differently on another target (the core is built with
// -ffp-contract=off). Points exactly on an edge go to the upper bin; a bin
// differs from floor(atan2 * T / 2 pi) only within rounding of an edge.
#ifndef PV_SURFACE_ANGLE_BINS_H
#define PV_SURFACE_ANGLE_BINS_H

#include <cstddef>
#include <cstdint>

namespace pv::surface {

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

// The tables live in caller memory sized by bytes_for(n) (the surface
// workspace): an MCU with 36 bins carries 36 bins' tables, not 360.
class AngleBins {
 public:
  static constexpr uint32_t kMaxBins = 360;

  // Bytes of the tables for n bins (8-byte aligned).
  static size_t bytes_for(uint32_t n);
  // n equal bins from angle 0, n <= kMaxBins; memory: bytes_for(n) bytes,
  // 8-byte aligned, kept for the object's life.
  void init(uint32_t n, void *memory);
  uint32_t bins() const { return n_; }

  uint32_t bin(double dx, double dy) const {
    const double d = diamond(dx, dy);
    auto j = uint32_t(d * double(per_unit_));
    if (j >= 4 * per_unit_) j = 4 * per_unit_ - 1;
    // A coarse cell is narrower than any bin (coarse_per_unit()), so it
    // meets at most two bins: one step.
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
  // Coarse cells per unit of diamond angle: at least 2.8 per bin on average
  // (256 for 360 bins), so a cell is narrower than the narrowest bin.
  static uint32_t coarse_per_unit(uint32_t n) { return n > 90 ? 256u : 64u; }
  uint32_t n_ = 0, per_unit_ = 0;
  const double *bound_ = nullptr;  // n + 1 edges, bound_[n] is +infinity
  const double *cc_ = nullptr, *cs_ = nullptr;  // n centre directions
  const uint16_t *start_ = nullptr;  // 4 * per_unit_ coarse cells
};

}  // namespace pv::surface

#endif
