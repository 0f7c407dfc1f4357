// The wall grid's and the floor map's geometry for one model, shared by the
// surface model's stages (surface_model.cpp, floor_map.cpp); internal to
// core/surface.
#ifndef PV_SURFACE_GRID_GEO_H
#define PV_SURFACE_GRID_GEO_H

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "common/divisor.h"
#include "surface/angle_bins.h"
#include "surface/surface_model.h"

namespace pv::surface {

// Bins and cells of the model: wall bins T (angle) x Z (height) of dz from
// z0; floor cells C x C of side cell from (fx0, fy0).
struct Geo {
  double z0, dz, fx0, fy0, cell;
  uint32_t T, Z, C;
  Divisor per_dz, per_cell;
};

inline Geo geo_of(const Workspace &ws, const Model &m, const Params &p) {
  return Geo{m.z0_mm, p.dz_mm, m.floor_x0, m.floor_y0, p.cell_mm, ws.cap.theta_bins, m.z_bins,
             ws.cap.cells, Divisor(p.dz_mm), Divisor(p.cell_mm)};
}

// A point over a floor cell that lies on the wall's surface where the wall
// overhangs the floor (a neck's underside and the flank above it, an
// undercut's foot) is wall, not a second floor: its radius reaches its wall
// bin's largest, less the bin's band and kFarWallMarginMm. Asked of the
// points in the floor's far window only (the slip checks), once the wall
// bins hold the first pass's radii. Small necking pits (tuning seeds 1323,
// 1324: 1 L, the neck 10-20 mm over the floor's outer cells) put 7-19 % of
// their floor's points there and were refused DOUBLED_FLOOR.
constexpr double kFarWallMarginMm = 2.0;
inline bool on_wall_surface(const Workspace &ws, const Geo &g, const Axis &axis, double wall_top,
                            double x, double y, double z) {
  if (z >= wall_top) return false;
  const double zb = g.per_dz.of(z - g.z0);
  if (zb < 0 || zb >= g.Z) return false;
  const double dx = x - axis.cx(z), dy = y - axis.cy(z);
  const WallBin &b = ws.wall[size_t(uint32_t(zb)) * g.T + ws.theta->bin(dx, dy)];
  return b.n_all > 0 && std::sqrt(dx * dx + dy * dy) >= double(b.top1) - double(b.band) - kFarWallMarginMm;
}

// The median (mean of the two middle values for even n), by selection, not
// a full sort: the same value, in a third of the time.
inline double median_small(float *v, size_t n) {
  std::nth_element(v, v + n / 2, v + n);
  if (n % 2) return double(v[n / 2]);
  const float below = *std::max_element(v, v + n / 2);
  return 0.5 * (double(below) + double(v[n / 2]));
}

// The share of a height histogram's total within its densest 3 bins (0 if
// empty): a second floor lies at one height (Model::floor_far_peak,
// FloorWeights::far_peak).
template <class T>
double densest_three_share(const T *h, uint32_t n) {
  double all = 0, peak = 0;
  for (uint32_t b = 0; b < n; ++b) all += double(h[b]);
  for (uint32_t b = 0; b + 2 < n; ++b) peak = std::max(peak, double(h[b]) + double(h[b + 1]) + double(h[b + 2]));
  return all > 0 ? peak / all : 0.0;
}

}  // namespace pv::surface

#endif
