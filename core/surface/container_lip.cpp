#include "surface/container_lip.h"

#include <algorithm>
#include <cmath>

namespace pv::surface {

namespace {

struct LipCtx {
  const AngleBins *bins;
  Axis axis;
  double lo, hi;        // the top band
  float *e1, *e2, *e3;  // pass 1: the three largest radii per bin
  float *l1, *l2, *l3;  // pass 1: the three smallest
  float *n_top;         // pass 1: points per bin
  const float *edge;    // pass 2: each bin's outer edge
  float *n_in;          // pass 2: points further in than kLipTolMm from it
  float *n_below, *n_below_out;  // pass 2: wall just below the band, and beyond the edge
  double below_lo, below_hi;
  bool second;
};

void lip_batch(void *c, const Point *pts, size_t count) {
  auto *x = static_cast<LipCtx *>(c);
  const double lo = x->lo, hi = x->hi;
  for (size_t k = 0; k < count; ++k) {
    const Point &q = pts[k];
    const bool below = x->second && q.z >= x->below_lo && q.z < x->below_hi;
    if ((q.z < lo || q.z > hi) && !below) continue;
    const double dx = q.x - x->axis.cx(q.z), dy = q.y - x->axis.cy(q.z);
    const uint32_t t = x->bins->bin(dx, dy);
    const auto r = float(std::sqrt(dx * dx + dy * dy));
    if (below) {
      x->n_below[t] += 1.0f;
      x->n_below_out[t] += r > x->edge[t] + float(kLipTolMm) ? 1.0f : 0.0f;
    } else if (!x->second) {
      const float a = x->e1[t], b = x->e2[t];
      x->e1[t] = std::max(a, r);
      x->e2[t] = std::max(b, std::min(a, r));
      x->e3[t] = std::max(x->e3[t], std::min(b, r));
      const float l = x->l1[t], m = x->l2[t];
      x->l1[t] = std::min(l, r);
      x->l2[t] = std::min(m, std::max(l, r));
      x->l3[t] = std::min(x->l3[t], std::max(m, r));
      x->n_top[t] += 1.0f;
    } else {
      x->n_in[t] += r < x->edge[t] - float(kLipTolMm) ? 1.0f : 0.0f;
    }
  }
}

// Bin t + d around the circle of T bins.
uint32_t around(uint32_t t, int d, uint32_t T) {
  return uint32_t((int64_t(t) + d + int64_t(T)) % int64_t(T));
}

}  // namespace

void lip_caps(const PointSource &src, const Workspace &ws, const Model &m, float *cap,
              float *scratch) {
  const uint32_t T = ws.cap.theta_bins;
  float *const s = scratch;
  float *const edge = s + 8 * size_t(T);
  float *const reach = s + 9 * size_t(T);  // window half-width, bins
  float *const hole = s + 10 * size_t(T);  // the inner edge
  LipCtx x{ws.theta, m.axis, m.rim_mm - kLipBandMm, m.rim_mm + kLipBandMm,
           s, s + T, s + 2 * T, s + 3 * T, s + 4 * T, s + 5 * T, s + 6 * T, edge, s + 7 * T,
           s + 11 * T, s + 12 * T, m.rim_mm - kLipBelowMm, m.rim_mm - kLipBandMm, false};
  std::fill(s, s + 3 * size_t(T), -HUGE_VALF);
  std::fill(s + 3 * size_t(T), s + 6 * size_t(T), HUGE_VALF);
  std::fill(s + 6 * size_t(T), s + 8 * size_t(T), 0.0f);
  std::fill(s + 11 * size_t(T), s + 13 * size_t(T), 0.0f);
  src.visit(src.ctx, lip_batch, &x);
  // A bin with too few top band points (a lip the scan saw from far) pools
  // the bins around it: its edges are the window's third largest and third
  // smallest radius (two strays beyond an edge do not move it).
  for (uint32_t t = 0; t < T; ++t) {
    float a = -HUGE_VALF, b = -HUGE_VALF, c = -HUGE_VALF, n = 0.0f;
    float la = HUGE_VALF, lb = HUGE_VALF, lc = HUGE_VALF;
    int d = 0;
    for (; d <= kLipMaxReach; ++d) {
      for (int side = d == 0 ? 1 : -1; side <= 1; side += 2) {
        const uint32_t u = around(t, side * d, T);
        for (const float v : {x.e1[u], x.e2[u], x.e3[u]}) {
          const float a0 = a, b0 = b;
          a = std::max(a0, v);
          b = std::max(b0, std::min(a0, v));
          c = std::max(c, std::min(b0, v));
        }
        for (const float v : {x.l1[u], x.l2[u], x.l3[u]}) {
          const float a0 = la, b0 = lb;
          la = std::min(a0, v);
          lb = std::min(b0, std::max(a0, v));
          lc = std::min(lc, std::max(b0, v));
        }
        n += x.n_top[u];
      }
      if (n >= float(kLipMinPoints)) break;
    }
    edge[t] = n >= float(kLipMinPoints) ? c : HUGE_VALF;
    hole[t] = lc;
    reach[t] = float(std::min(d, kLipMaxReach));
  }
  x.second = true;
  src.visit(src.ctx, lip_batch, &x);
  for (uint32_t t = 0; t < T; ++t) {
    float n = 0.0f, in = 0.0f, nb = 0.0f, nb_out = 0.0f;
    const int r = int(reach[t]);
    for (int d = -r; d <= r; ++d) {
      n += x.n_top[around(t, d, T)];
      in += x.n_in[around(t, d, T)];
      nb += x.n_below[around(t, d, T)];
      nb_out += x.n_below_out[around(t, d, T)];
    }
    const bool flat = edge[t] < HUGE_VALF && in >= float(kLipFlatShare) * n &&
                      hole[t] >= float(kLipMinHole) * edge[t] && 2.0f * nb_out < nb + 1.0f;
    cap[t] = flat ? edge[t] - float(kLipTolMm) : HUGE_VALF;
  }
  // Where most of the round is flat (a container, a ground ring), a bin the
  // scan saw too little of the lip in takes its cap from its own inner edge
  // and the flat bins' median width: a vessel's wall is as thick all round.
  float *const width = s;  // the largest radii are spent
  size_t flat = 0, known = 0;
  for (uint32_t t = 0; t < T; ++t) {
    if (!(hole[t] < HUGE_VALF)) continue;
    ++known;
    if (cap[t] < HUGE_VALF) width[flat++] = cap[t] + float(kLipTolMm) - hole[t];
  }
  if (flat == 0 || 2 * flat < known) return;
  std::nth_element(width, width + flat / 2, width + flat);
  const float w = width[flat / 2];
  for (uint32_t t = 0; t < T; ++t) {
    if (!(cap[t] < HUGE_VALF) && hole[t] < HUGE_VALF) cap[t] = hole[t] + w - float(kLipTolMm);
  }
}

}  // namespace pv::surface
