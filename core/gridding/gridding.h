// Z gridding (paper 3.4): z_norm = dz * round(z / dz).
//
// A layer is identified by its index j; layer j holds the points whose
// levelled z rounds to (j - j0) * dz, where j0 layers lie below the bottom
// plane (z = 0) to catch the bottom's range noise. The same mapping serves
// the provisional bins (while streaming) and the final layers (at finish).
#ifndef PV_GRIDDING_GRIDDING_H
#define PV_GRIDDING_GRIDDING_H

#include <cmath>
#include <cstdint>

namespace pv::gridding {

struct Grid {
  double layer_mm = 0.5;
  uint32_t layers = 0;      // total, including the j0 below the bottom
  uint32_t below = 0;       // j0

  // Index of the layer holding levelled height z, or -1 outside the grid.
  int64_t layer_of(double z_mm) const {
    // floor(x + 0.5): round half up, the same on every platform and for
    // every sign (std::round would round -0.5 away from zero).
    const double q = std::floor(z_mm / layer_mm + 0.5);
    if (!(q >= -double(below)) || q >= double(layers - below)) return -1;
    return int64_t(q) + int64_t(below);
  }
  double z_of(uint32_t j) const { return (double(j) - double(below)) * layer_mm; }
  double top_mm() const { return z_of(layers - 1); }
};

// Layers kept below the bottom plane: a few millimetres, at least 2 layers.
inline uint32_t layers_below(double layer_mm) {
  const double below_mm = 4.0;
  const auto n = uint32_t(std::ceil(below_mm / layer_mm));
  return n < 2 ? 2 : n;
}

}  // namespace pv::gridding

#endif
