// Small value types shared by the stages of the core. No allocation, no I/O.
#ifndef PV_COMMON_GEOMETRY_H
#define PV_COMMON_GEOMETRY_H

#include <cstddef>
#include <cstdint>

namespace pv {

// A point of one layer, projected on the levelled XY plane (millimetres).
// Layers are processed in double: a fit over a few hundred points of a
// 100 mm contour must not lose the 0.01 mm the area accuracy rests on.
struct XY {
  double x_mm;
  double y_mm;
};

// A coordinate this far out (a kilometre) is no scanner's: the point is
// invalid, as NaN and infinities are (the session's validity check and the
// duplicate filter's, which must agree).
constexpr float kAbsurdMm = 1.0e6f;

// A stored point, raw scanner frame (millimetres); same layout as pv_point_t.
struct P3 {
  float x_mm;
  float y_mm;
  float z_mm;
};

// A view over caller-owned memory: pointer + count, capacity not in the type.
template <class T>
struct Span {
  T *data = nullptr;
  size_t size = 0;
  T &operator[](size_t i) const { return data[i]; }
  T *begin() const { return data; }
  T *end() const { return data + size; }
};

}  // namespace pv

#endif
