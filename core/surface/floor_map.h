// The floor map's stages after the grid passes (surface::build): fill the
// cells the scan missed, flood the floor from its lowest cells, drop the
// bumps multipath leaves on it. Internal to core/surface.
#ifndef PV_SURFACE_FLOOR_MAP_H
#define PV_SURFACE_FLOOR_MAP_H

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "surface/grid_geo.h"
#include "surface/surface_model.h"

namespace pv::surface {

// The part of the floor map a scan over its cells visits: the bounding box
// of the cells that are not empty, grown as the fill spreads. Most of the
// map lies outside the pit and stays empty; a scan of the box in row order
// meets the same cells in the same order as a scan of the whole map.
struct CellBox {
  uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1); empty if x0 >= x1
  void add(uint32_t x, uint32_t y) {
    if (x0 >= x1) {
      x0 = x, y0 = y, x1 = x + 1, y1 = y + 1;
      return;
    }
    x0 = std::min(x0, x), y0 = std::min(y0, y);
    x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
  }
  // By d cells each way, within the C x C map.
  void grow(uint32_t d, uint32_t C) {
    if (x0 >= x1) return;
    x0 = x0 > d ? x0 - d : 0, y0 = y0 > d ? y0 - d : 0;
    x1 = std::min(x1 + d, C), y1 = std::min(y1 + d, C);
  }
  template <class F>
  void each(uint32_t C, F f) const {  // f(index, x, y), row by row
    if (x0 >= x1) return;
    for (uint32_t y = y0; y < y1; ++y) {
      for (uint32_t x = x0; x < x1; ++x) f(size_t(y) * C + x, x, y);
    }
  }
};

// Floor cells without points inside the pit, from their neighbours (a few
// rounds); grows box over the cells it fills.
void fill_floor(Workspace &ws, const Geo &g, CellBox *box);
// The floor: the cells connected to the lowest above the floor plane
// without a step (kFloor).
void flood_floor(Workspace &ws, const Geo &g, const Params &p, const FloorPlane &plane,
                 const CellBox &box);
// Floor cells well above the median of the floor around them leave the floor.
void drop_floor_bumps(Workspace &ws, const Geo &g, const Params &p, const CellBox &box);

}  // namespace pv::surface

#endif
