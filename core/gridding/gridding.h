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

#include "common/geometry.h"

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

// The ingest path's form of Grid::layer_of(levelled z): the levelling row,
// the 1/dz scale and the offsets folded into one dot product, and floor()
// replaced by truncation of a value known to be >= 0. A division and a
// floor() per point were the largest cost of push() (the baseline x86-64
// ISA has no rounding instruction). It may differ from layer_of() in the
// last bit at a layer boundary; it only chooses the provisional bin, and
// finish() re-assigns every point with layer_of().
struct LayerMap {
  double a = 0, b = 0, c = 0, d = 0;  // q = a x + b y + c z + d
  double layers = 0;
  double index_of(const P3 &p) const { return a * p.x_mm + b * p.y_mm + c * p.z_mm + d; }
  int64_t layer_of(const P3 &p) const {
    const double q = index_of(p);
    if (!(q >= 0.0) || q >= layers) return -1;
    return int64_t(q);
  }
  // Outside the grid above its top (layer_of() is -1 for it).
  bool above(const P3 &p) const { return index_of(p) >= layers; }
};

// level_row, level_t_z: z_levelled = level_row . p + level_t_z.
inline LayerMap layer_map(const Grid &g, const double level_row[3], double level_t_z) {
  const double inv = 1.0 / g.layer_mm;
  return LayerMap{level_row[0] * inv, level_row[1] * inv, level_row[2] * inv,
                  level_t_z * inv + double(g.below) + 0.5, double(g.layers)};
}

// Layers kept below the bottom plane: a few millimetres, at least 2 layers.
// The plane is fitted to the lowest few percent of the scan; a curved or
// uneven floor (a bowl, a hand-dug pit) reaches well below it, which the
// surface method measures (kSurfaceBelowMm): there the band is deeper.
constexpr double kBelowMm = 4.0;
constexpr double kSurfaceBelowMm = 40.0;
inline uint32_t layers_below(double layer_mm, double below_mm = kBelowMm) {
  const auto n = uint32_t(std::ceil(below_mm / layer_mm));
  return n < 2 ? 2 : n;
}

}  // namespace pv::gridding

#endif
