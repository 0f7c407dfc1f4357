// a / d as a product where 1 / d is exact (d a power of two, as the
// default 0.5 mm layers and 2 mm wall bins and floor cells): the same bits
// as the division, without a division per point (a division per point
// was measurable on the ingest path and in every pass of the model).
#ifndef PV_COMMON_DIVISOR_H
#define PV_COMMON_DIVISOR_H

#include <cmath>

namespace pv {

struct Divisor {
  double d, inv;
  bool exact;
  explicit Divisor(double v) : d(v), inv(1.0 / v) {
    int e = 0;
    exact = std::frexp(v, &e) == 0.5;
  }
  double of(double a) const { return exact ? a * inv : a / d; }
};

}  // namespace pv

#endif
