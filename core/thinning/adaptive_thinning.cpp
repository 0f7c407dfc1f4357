// Adaptive thinning of one layer: see adaptive_thinning.h for the method,
// the decisions and the neighbour grid. Everything here works on caller
// memory (the session block): no heap, no exceptions.
#include "thinning/adaptive_thinning.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pv {
namespace thinning {

namespace {

enum : uint8_t { kUnhandled = 0, kKept = 1, kSampled = 2 };

// The kNN search stops once its k-th distance is below the ring bound by
// this relative margin, so that rounding in the cell index of a point can
// never hide a nearer point in an unvisited ring.
constexpr double kRingMargin = 1.0 - 1e-9;

// Hashed uniform grid over the canonical points of one layer. Cell indices
// come from one function (cell_of) for the points and for the queries, and
// it is monotone in x and y, so range queries over cells are exact.
class NeighbourGrid {
 public:
  NeighbourGrid(const XY *pts, size_t n, uint32_t k, const Workspace &ws)
      : pts_(pts), start_(ws.grid_start), items_(ws.grid_items) {
    double min_y = pts[0].y_mm;
    double max_y = min_y;
    for (size_t i = 1; i < n; ++i) {
      min_y = std::min(min_y, pts[i].y_mm);
      max_y = std::max(max_y, pts[i].y_mm);
    }
    min_x_ = pts[0].x_mm;  // canonical: sorted by x
    min_y_ = min_y;
    const double extent = (pts[n - 1].x_mm - min_x_) + (max_y - min_y);
    // About k + 1 points per cell along a contour (see the header).
    double h = extent * static_cast<double>(k + 1) / static_cast<double>(n);
    if (!(h > 0.0) || !std::isfinite(h)) h = 1.0;  // all points coincide
    h_ = h;
    inv_h_ = 1.0 / h;
    nx_ = raw_cell(pts[n - 1].x_mm, min_x_) + 1;
    ny_ = raw_cell(max_y, min_y_) + 1;
    buckets_ = 1;
    while (buckets_ * 2 <= n) buckets_ *= 2;
    build(n);
  }

  double cell_side_mm() const { return h_; }
  int64_t nx() const { return nx_; }
  int64_t ny() const { return ny_; }
  int64_t cell_x(double x) const { return clamp(raw_cell(x, min_x_), nx_); }
  int64_t cell_y(double y) const { return clamp(raw_cell(y, min_y_), ny_); }

  // Calls f(index) for every point in cell (cx, cy), in canonical order.
  template <class F>
  void for_each_in_cell(int64_t cx, int64_t cy, F &&f) const {
    const uint32_t b = bucket(cx, cy);
    for (uint32_t q = start_[b]; q < start_[b + 1]; ++q) {
      const uint32_t i = items_[q];
      if (cell_x(pts_[i].x_mm) == cx && cell_y(pts_[i].y_mm) == cy) f(i);
    }
  }

 private:
  // Truncation, not floor: v >= lo for every point (lo is the minimum), so
  // both agree there, and truncation is monotone too (queries below lo clamp
  // to cell 0 either way). It is also one instruction, where floor is a libm
  // call on baseline x86-64.
  int64_t raw_cell(double v, double lo) const {
    return static_cast<int64_t>((v - lo) * inv_h_);
  }
  static int64_t clamp(int64_t c, int64_t n) { return c < 0 ? 0 : (c >= n ? n - 1 : c); }
  uint32_t bucket(int64_t cx, int64_t cy) const {
    const uint32_t hx = static_cast<uint32_t>(cx) * 0x9E3779B1u;
    const uint32_t hy = static_cast<uint32_t>(cy) * 0x85EBCA77u;
    return (hx ^ (hy >> 7) ^ hy) & static_cast<uint32_t>(buckets_ - 1);
  }
  // Counting sort of the point indices by bucket (stable: canonical order
  // inside a bucket).
  void build(size_t n) {
    std::fill(start_, start_ + buckets_ + 1, uint32_t{0});
    for (size_t i = 0; i < n; ++i)
      ++start_[bucket(cell_x(pts_[i].x_mm), cell_y(pts_[i].y_mm)) + 1];
    for (size_t b = 0; b < buckets_; ++b) start_[b + 1] += start_[b];
    // Place with start[b] as the cursor, then shift the starts back.
    for (size_t i = 0; i < n; ++i)
      items_[start_[bucket(cell_x(pts_[i].x_mm), cell_y(pts_[i].y_mm))]++] =
          static_cast<uint32_t>(i);
    for (size_t b = buckets_; b > 0; --b) start_[b] = start_[b - 1];
    start_[0] = 0;
  }

  const XY *pts_;
  uint32_t *start_;
  uint32_t *items_;
  double min_x_ = 0.0, min_y_ = 0.0, h_ = 1.0, inv_h_ = 1.0;
  int64_t nx_ = 1, ny_ = 1;
  size_t buckets_ = 1;
};

bool less_xy(const XY &a, const XY &b) {
  if (a.x_mm != b.x_mm) return a.x_mm < b.x_mm;
  return a.y_mm < b.y_mm;
}

uint32_t clamp_k(uint32_t k) {
  return std::min(std::max(k, uint32_t{1}), kMaxKnnK);
}

double dist_sq(const XY &a, const XY &b) {
  const double dx = a.x_mm - b.x_mm;
  const double dy = a.y_mm - b.y_mm;
  return dx * dx + dy * dy;
}

// Mean distance to the k nearest neighbours of point i (itself excluded).
// The k + 1 smallest squared distances are kept sorted; the point finds
// itself at distance 0, so summing all k + 1 distances and dividing by k
// drops exactly that zero, whichever of several duplicates is "itself".
double mean_knn_dist_mm(const NeighbourGrid &g, const XY *pts, size_t i, uint32_t k) {
  double best[kMaxKnnK + 1];
  uint32_t count = 0;
  const uint32_t want = k + 1;
  const XY &q = pts[i];
  auto offer = [&](uint32_t j) {
    const double d2 = dist_sq(q, pts[j]);
    if (count == want && !(d2 < best[want - 1])) return;
    uint32_t w = count < want ? count++ : want - 1;
    while (w > 0 && best[w - 1] > d2) {
      best[w] = best[w - 1];
      --w;
    }
    best[w] = d2;
  };
  const int64_t qx = g.cell_x(q.x_mm), qy = g.cell_y(q.y_mm);
  const int64_t r_max = std::max(g.nx(), g.ny());
  for (int64_t r = 0; r <= r_max; ++r) {
    const int64_t x0 = std::max<int64_t>(qx - r, 0), x1 = std::min(qx + r, g.nx() - 1);
    const int64_t y0 = std::max<int64_t>(qy - r, 0), y1 = std::min(qy + r, g.ny() - 1);
    for (int64_t cx = x0; cx <= x1; ++cx) {
      const bool edge_x = (cx == qx - r || cx == qx + r);
      for (int64_t cy = y0; cy <= y1; ++cy) {
        // Only the ring at Chebyshev distance r: inner cells are done.
        if (!edge_x && cy != qy - r && cy != qy + r) {
          cy = std::max(cy, qy + r - 1);  // jump to the ring's far row
          continue;
        }
        g.for_each_in_cell(cx, cy, offer);
      }
    }
    // Any point in a cell beyond ring r lies more than r cells away along
    // one axis, i.e. farther than r * h: the k + 1 best are final.
    if (count == want) {
      const double bound = static_cast<double>(r) * g.cell_side_mm() * kRingMargin;
      if (best[want - 1] < bound * bound) break;
    }
  }
  double sum = 0.0;
  // Ascending order: equal distances are equal values, so the sum is a
  // function of the distance multiset only.
  for (uint32_t j = 0; j < count; ++j) sum += std::sqrt(best[j]);
  return std::max(sum / static_cast<double>(k), kMinMeanDistMm);
}

// Step 3.5.1 + 3.5.2: fills spacing_mm[i] with s_i.
void compute_spacing(const NeighbourGrid &g, const XY *pts, size_t n, uint32_t k,
                     double s0_mm, double *spacing_mm) {
  double rho_min = std::numeric_limits<double>::infinity();
  double rho_max = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double rho = 1.0 / mean_knn_dist_mm(g, pts, i, k);
    spacing_mm[i] = rho;  // hold rho until the extremes are known
    rho_min = std::min(rho_min, rho);
    rho_max = std::max(rho_max, rho);
  }
  for (size_t i = 0; i < n; ++i)
    spacing_mm[i] = spacing_from_density(spacing_mm[i], rho_min, rho_max, s0_mm);
}

// Of the candidates of one square (in canonical order), the one nearest
// their centroid; ties go to the lower canonical index.
uint32_t pick_nearest_centroid(const XY *pts, const uint32_t *cand, size_t m) {
  double sx = 0.0, sy = 0.0;
  for (size_t j = 0; j < m; ++j) {
    sx += pts[cand[j]].x_mm;
    sy += pts[cand[j]].y_mm;
  }
  const double cx = sx / static_cast<double>(m);
  const double cy = sy / static_cast<double>(m);
  uint32_t best = cand[0];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < m; ++j) {
    const double d2 = dist_sq(pts[cand[j]], XY{cx, cy});
    if (d2 < best_d2 || (d2 == best_d2 && cand[j] < best)) {
      best_d2 = d2;
      best = cand[j];
    }
  }
  return best;
}

// The unhandled points of the square |dx|, |dy| <= half around point i,
// into out[] in canonical order; returns their count.
size_t gather_square(const NeighbourGrid &g, const XY *pts, const uint8_t *state, size_t i,
                     double half_mm, uint32_t *out, size_t cap) {
  const XY &c = pts[i];
  // One cell of slack each side: the corners are computed in rounded
  // arithmetic; the exact test is the one on |dx|, |dy| below.
  const int64_t x0 = std::max<int64_t>(g.cell_x(c.x_mm - half_mm) - 1, 0);
  const int64_t x1 = std::min(g.cell_x(c.x_mm + half_mm) + 1, g.nx() - 1);
  const int64_t y0 = std::max<int64_t>(g.cell_y(c.y_mm - half_mm) - 1, 0);
  const int64_t y1 = std::min(g.cell_y(c.y_mm + half_mm) + 1, g.ny() - 1);
  size_t m = 0;
  for (int64_t cx = x0; cx <= x1; ++cx) {
    for (int64_t cy = y0; cy <= y1; ++cy) {
      g.for_each_in_cell(cx, cy, [&](uint32_t j) {
        if (state[j] != kUnhandled || m == cap) return;
        if (std::fabs(pts[j].x_mm - c.x_mm) > half_mm) return;
        if (std::fabs(pts[j].y_mm - c.y_mm) > half_mm) return;
        out[m++] = j;
      });
    }
  }
  std::sort(out, out + m);  // canonical order: the centroid sum is fixed
  return m;
}

// Step 3.5.3: local-grid optimal sampling, marks ws.state.
void sample_cells(const NeighbourGrid &g, const XY *pts, size_t n, const Workspace &ws) {
  std::fill(ws.state, ws.state + n, uint8_t{kUnhandled});
  for (size_t i = 0; i < n; ++i) {
    if (ws.state[i] != kUnhandled) continue;
    size_t m = gather_square(g, pts, ws.state, i, 0.5 * ws.spacing_mm[i], ws.candidates, n);
    if (m == 0) {  // the point itself is always inside; guard anyway
      ws.candidates[0] = static_cast<uint32_t>(i);
      m = 1;
    }
    const uint32_t keep = pick_nearest_centroid(pts, ws.candidates, m);
    for (size_t j = 0; j < m; ++j) ws.state[ws.candidates[j]] = kSampled;
    ws.state[keep] = kKept;
  }
}

// Moves the kept points to the front, preserving canonical order.
size_t compact_kept(XY *pts, size_t n, const uint8_t *state) {
  size_t w = 0;
  for (size_t i = 0; i < n; ++i)
    if (state[i] == kKept) pts[w++] = pts[i];
  return w;
}

bool usable(const Workspace &ws, size_t n) {
  return ws.spacing_mm != nullptr && ws.state != nullptr && ws.candidates != nullptr &&
         ws.grid_items != nullptr && ws.grid_start != nullptr && ws.capacity >= n &&
         n <= UINT32_MAX;
}

}  // namespace

size_t workspace_bytes_per_point() {
  return sizeof(double) + sizeof(uint8_t) + 3 * sizeof(uint32_t);
}

size_t workspace_bytes(size_t n) {
  // One more bucket start, and slack for aligning the double and uint32
  // arrays inside an arbitrary block.
  return n * workspace_bytes_per_point() + sizeof(uint32_t) + alignof(double) +
         alignof(uint32_t);
}

bool make_workspace(void *block, size_t block_bytes, size_t n, Workspace *ws) {
  if (block == nullptr || ws == nullptr || block_bytes < workspace_bytes(n)) return false;
  uintptr_t p = reinterpret_cast<uintptr_t>(block);
  p = (p + alignof(double) - 1) & ~static_cast<uintptr_t>(alignof(double) - 1);
  double *spacing = reinterpret_cast<double *>(p);
  p += n * sizeof(double);  // still aligned for uint32_t
  uint32_t *cand = reinterpret_cast<uint32_t *>(p);
  p += n * sizeof(uint32_t);
  uint32_t *items = reinterpret_cast<uint32_t *>(p);
  p += n * sizeof(uint32_t);
  uint32_t *start = reinterpret_cast<uint32_t *>(p);  // at most n buckets + 1
  p += (n + 1) * sizeof(uint32_t);
  ws->spacing_mm = spacing;
  ws->candidates = cand;
  ws->grid_items = items;
  ws->grid_start = start;
  ws->state = reinterpret_cast<uint8_t *>(p);
  ws->capacity = n;
  return true;
}

double spacing_from_density(double rho, double rho_min, double rho_max, double s0_mm) {
  const double span = rho_max - rho_min;
  // Uniform layer: no gradient to follow, take the cautious (finest) spacing.
  const double t = (span > 0.0) ? (rho - rho_min) / span : 0.0;
  const double s = 0.5 * s0_mm + t * 1.5 * s0_mm;
  return std::min(std::max(s, 0.5 * s0_mm), 2.0 * s0_mm);
}

size_t canonicalize(XY *pts, size_t n) {
  size_t w = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(pts[i].x_mm) || !std::isfinite(pts[i].y_mm)) continue;
    // -0.0 == +0.0 for the sort but not for the output bits: unify them.
    pts[w].x_mm = pts[i].x_mm + 0.0;
    pts[w].y_mm = pts[i].y_mm + 0.0;
    ++w;
  }
  std::sort(pts, pts + w, less_xy);  // introsort: in place, no allocation
  return w;
}

bool mean_knn_distances(const XY *pts, size_t n, uint32_t k, const Workspace &ws, double *d_mm) {
  k = clamp_k(k);
  if (pts == nullptr || d_mm == nullptr || !usable(ws, n) || n < static_cast<size_t>(k) + 1)
    return false;
  const NeighbourGrid g(pts, n, k, ws);
  for (size_t i = 0; i < n; ++i) d_mm[i] = mean_knn_dist_mm(g, pts, i, k);
  return true;
}

size_t thin_layer(XY *pts, size_t n, const Params &p, const Workspace &ws) {
  if (pts == nullptr || n == 0) return 0;
  if (!usable(ws, n)) return n;
  n = canonicalize(pts, n);
  const uint32_t k = clamp_k(p.knn_k);
  if (n < static_cast<size_t>(k) + 1 || !(p.s0_mm > 0.0)) return n;

  const NeighbourGrid grid(pts, n, k, ws);
  compute_spacing(grid, pts, n, k, p.s0_mm, ws.spacing_mm);
  sample_cells(grid, pts, n, ws);
  return compact_kept(pts, n, ws.state);
}

}  // namespace thinning
}  // namespace pv
