#include "surface/floor_map.h"

#include <algorithm>
#include <cmath>

namespace pv::surface {

namespace {

// Floor cells without points inside the pit: from their neighbours, a few
// rounds (holes of dropout); cells still empty set no floor constraint.
// Each round reads only values of earlier rounds. After the first, a cell
// can only become fillable next to a cell the last round filled, so later
// rounds look at those neighbours alone, not at every cell of the map (most
// lie outside the pit): the same fills, without eight scans of the map.
constexpr float kQueuedCell = -1.0e30f;  // an empty cell's value, while queued

// fn(j) for the index j of each of cell (x, y)'s four neighbours inside the
// C x C map, in a fixed order (+x, -x, +y, -y): the fill's sums add in it.
template <class Fn>
inline void for_each_neighbour(uint32_t C, uint32_t x, uint32_t y, Fn &&fn) {
  for (int d = 0; d < 4; ++d) {
    const int xx = int(x) + (d == 0) - (d == 1), yy = int(y) + (d == 2) - (d == 3);
    if (xx < 0 || yy < 0 || xx >= int(C) || yy >= int(C)) continue;
    fn(size_t(yy) * C + size_t(xx));
  }
}

void fill_floor_cell(Workspace &ws, uint32_t C, uint32_t x, uint32_t y, size_t *k) {
  const size_t i = size_t(y) * C + x;
  if (ws.floor[i].state != kEmpty) return;
  double s = 0;
  int cnt = 0;
  for_each_neighbour(C, x, y, [&](size_t j) {
    const FloorCell &o = ws.floor[j];
    if (o.state == kEmpty) return;
    s += o.value;
    ++cnt;
  });
  if (cnt < 2) return;
  ws.fill_idx[*k] = uint32_t(i);
  ws.fill_val[*k] = float(s / cnt);
  ++*k;
}

// The seeds of the flood over the cells' heights above a plane: those at
// most floor_seed_mm above the lowest cells, or above the plane when lower
// cells are few (the floor layers are thinned hardest, the multipath above
// them not at all: a cell of multipath can be lower than the 2 % quantile
// of a sparse floor's cells otherwise).
struct Seeds {
  FloorPlane plane;
  float below = 0.0f;  // seeds: at most this above the plane
  size_t cells = 0;    // how many
};
float above(const Geo &g, const FloorPlane &plane, uint32_t x, uint32_t y, float v) {
  return float(double(v) - plane.at(g.fx0 + (x + 0.5) * g.cell, g.fy0 + (y + 0.5) * g.cell));
}
Seeds seeds_over(Workspace &ws, const Geo &g, const Params &p, const FloorPlane &plane, const CellBox &box) {
  Seeds s{plane};
  size_t n = 0;
  box.each(g.C, [&](size_t i, uint32_t x, uint32_t y) {
    if (ws.floor[i].state != kEmpty) ws.fill_val[n++] = above(g, plane, x, y, ws.floor[i].value);
  });
  if (n == 0) return s;
  const size_t q = n / 50;  // 2 % quantile
  std::nth_element(ws.fill_val, ws.fill_val + q, ws.fill_val + n);
  s.below = std::min(ws.fill_val[q], 0.0f) + float(p.floor_seed_mm);
  box.each(g.C, [&](size_t i, uint32_t x, uint32_t y) {
    if (ws.floor[i].state != kEmpty && above(g, plane, x, y, ws.floor[i].value) <= s.below) ++s.cells;
  });
  return s;
}

}  // namespace

// The floor is the surface connected to the lowest cells without a step:
// flood from them, accepting a neighbour that rises at most max_rise_mm
// (any descent is accepted). Multipath floating above the floor, block tops
// and ledges are separated from it by a step: they set no floor constraint,
// the wall grid bounds the void there.
// Lowest above which plane: where the ground tilts against the floor (a
// pit dug into a slope) the floor is a ramp in the opening's frame, and a
// sparse floor (a wide pit's, a point or two a cell) is no connected
// surface from its lowest cells up: seeded by height alone, the flood took
// the ramp's lowest 8 mm and the void below z = 0 was lost (a 0.45 m3
// cylinder in a 4 deg slope, -0.62 % against +/- 0.40 %: tuning seed 1334
// #786). Above the levelling's floor plane the whole ramp seeds. But the
// floor fit can miss the floor (a shallow wide pit's, 4-13 deg off through
// the wall's foot), and that plane crosses the floor in a strip: of z = 0
// and the floor plane, the one under which more cells seed is the floor's
// (#786: 6,582 cells against 82; 1335 #170, a shallow pit whose floor fit
// is 12.8 deg off: 98 against 7,338). Where nothing seeds at z = 0 the
// floor does not reach the floor fit's plane: a rounded bowl, whose fit
// is a tangent plane 10-14 deg off, and whose wall grid bounds the void
// better than a flood over its curve (fresh seed 1338 #343's single pass:
// +0.24 % from the wall grid, -0.85 % against +/- 0.65 % flooded from the
// plane).
void flood_floor(Workspace &ws, const Geo &g, const Params &p, const FloorPlane &plane,
                 const CellBox &box) {
  const uint32_t C = g.C;
  Seeds seeds = seeds_over(ws, g, p, FloorPlane{}, box);
  if (seeds.cells > 0 && (plane.a != 0.0 || plane.b != 0.0 || plane.c != 0.0)) {
    const Seeds tilted = seeds_over(ws, g, p, plane, box);
    if (tilted.cells > seeds.cells) seeds = tilted;
  }
  size_t head = 0, tail = 0;
  box.each(C, [&](size_t i, uint32_t x, uint32_t y) {
    FloorCell &f = ws.floor[i];
    if (f.state != kEmpty && above(g, seeds.plane, x, y, f.value) <= seeds.below) {
      f.state = kFloor;
      ws.queue[tail++] = uint32_t(i);
    }
  });
  // A step is a rise per cell; coarse cells (Params::coarse_bins) take the
  // same slope as the default 2 mm cells: 12 mm cells stopped the flood on
  // a bowl's sides, whose floor then continued flat from the bottom (+0.5
  // to +1 %).
  const float rise = float(p.coarse_bins ? p.floor_max_rise_mm * g.cell / Params{}.cell_mm
                                         : p.floor_max_rise_mm);
  while (head < tail) {
    const uint32_t i = ws.queue[head++];
    const uint32_t x = i % C, y = i / C;
    const float v = ws.floor[i].value;
    for_each_neighbour(C, x, y, [&](size_t j) {
      FloorCell &o = ws.floor[j];
      if (o.state == kEmpty || o.state == kFloor || o.value > v + rise) return;
      o.state = kFloor;
      ws.queue[tail++] = uint32_t(j);
    });
  }
}

// A floor cell more than floor_bump_mm above the median of the floor cells
// around it (5 x 5) is multipath that the flood reached by a small step,
// not floor: dropped, the floor is carried from around it.
void drop_floor_bumps(Workspace &ws, const Geo &g, const Params &p, const CellBox &box) {
  const uint32_t C = g.C;
  float nb[24];
  size_t k = 0;
  box.each(C, [&](size_t i, uint32_t x, uint32_t y) {
    if (ws.floor[i].state != kFloor) return;
    size_t n = 0;
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        const int xx = int(x) + dx, yy = int(y) + dy;
        if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= int(C) || yy >= int(C)) continue;
        const FloorCell &o = ws.floor[size_t(yy) * C + size_t(xx)];
        if (o.state == kFloor) nb[n++] = o.value;
      }
    }
    if (n < 4) return;
    // Not above the lowest neighbour by the bump: not above the median.
    const double v = ws.floor[i].value;
    if (v <= double(*std::min_element(nb, nb + n)) + p.floor_bump_mm) return;
    if (v > median_small(nb, n) + p.floor_bump_mm) ws.queue[k++] = uint32_t(i);
  });
  for (size_t q = 0; q < k; ++q) ws.floor[ws.queue[q]].state = kSeen;
}

// Grows box over the cells it fills.
void fill_floor(Workspace &ws, const Geo &g, CellBox *box) {
  const uint32_t C = g.C;
  // fill_idx holds a round's fills: at most its capacity (theta x z bins).
  const size_t cap = size_t(ws.cap.theta_bins) * ws.cap.z_bins;
  size_t queued = 0;  // candidates of this round in ws.queue
  for (int round = 0; round < 8; ++round) {
    size_t k = 0;
    box->grow(1, C);  // a round fills next to cells that are not empty
    if (round == 0) {
      const CellBox &b = *box;
      for (uint32_t y = b.y0; y < b.y1 && k + 1 < cap; ++y) {
        for (uint32_t x = b.x0; x < b.x1 && k + 1 < cap; ++x) fill_floor_cell(ws, C, x, y, &k);
      }
    } else {
      for (size_t q = 0; q < queued && k + 1 < cap; ++q) {
        const uint32_t i = ws.queue[q];
        ws.floor[i].value = 0.0f;
        fill_floor_cell(ws, C, i % C, i / C, &k);
      }
      for (size_t q = 0; q < queued; ++q) ws.floor[ws.queue[q]].value = 0.0f;
    }
    if (k == 0) break;
    for (size_t q = 0; q < k; ++q) {
      ws.floor[ws.fill_idx[q]].value = ws.fill_val[q];
      ws.floor[ws.fill_idx[q]].state = kBridged;
    }
    queued = 0;
    for (size_t q = 0; q < k; ++q) {
      const uint32_t i = ws.fill_idx[q], x = i % C, y = i / C;
      for_each_neighbour(C, x, y, [&](size_t j) {
        FloorCell &o = ws.floor[j];
        if (o.state != kEmpty || o.value == kQueuedCell) return;
        o.value = kQueuedCell;
        ws.queue[queued++] = uint32_t(j);
      });
    }
  }
  for (size_t q = 0; q < queued; ++q) ws.floor[ws.queue[q]].value = 0.0f;
}

FloorWeights start_floor_weights(const Workspace &ws, const Model &m, const Params &p) {
  const Geo g = geo_of(ws, m, p);
  float top = -HUGE_VALF;
  const size_t cells = size_t(g.C) * g.C;
  for (size_t i = 0; i < cells; ++i) {
    if (ws.floor[i].state == kFloor) top = std::max(top, ws.floor[i].value);
  }
  FloorWeights w;
  w.z_top = double(top) + p.band_mm + p.slip_mm;
  return w;
}

void weigh_floor(const Workspace &ws, const Model &m, const Params &p, const Point *pts, size_t n,
                 double weight, FloorWeights *acc) {
  const Geo g = geo_of(ws, m, p);
  const double far_from = p.band_mm + p.ghost_mm, far_to = p.band_mm + p.slip_mm;
  const double wall_top = m.rim_mm - p.rim_guard_mm;  // as the wall grid's passes
  for (size_t k = 0; k < n; ++k) {
    const Point &q = pts[k];
    if (q.z > acc->z_top) continue;
    const double fx = g.per_cell.of(q.x - g.fx0), fy = g.per_cell.of(q.y - g.fy0);
    if (!(fx >= 0 && fy >= 0 && fx < g.C && fy < g.C)) continue;
    const FloorCell &f = ws.floor[size_t(uint32_t(fy)) * g.C + uint32_t(fx)];
    if (f.state != kFloor) continue;
    const double h = q.z - double(f.value);
    if (std::fabs(h) <= p.band_mm) {
      acc->floor += weight;
    } else if (h > far_from && h <= far_to && !on_wall_surface(ws, g, m.axis, wall_top, q.x, q.y, q.z)) {
      acc->far += weight;
      const auto b = uint32_t(h - far_from);
      acc->hist[b < kFloorSlipBins ? b : kFloorSlipBins - 1] += weight;
    }
  }
}

double FloorWeights::far_peak() const { return densest_three_share(hist, kFloorSlipBins); }

}  // namespace pv::surface
