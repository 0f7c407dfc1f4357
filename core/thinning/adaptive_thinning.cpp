// Adaptive thinning of one layer: see adaptive_thinning.h for the method and
// the decisions. Everything here works on caller memory, except the kd-tree
// build (documented exception).
#include "thinning/adaptive_thinning.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <nanoflann.hpp>

namespace pv {
namespace thinning {

namespace {

enum : uint8_t { kUnhandled = 0, kKept = 1, kSampled = 2 };

// nanoflann dataset adaptor over the caller's points (no copy).
struct LayerCloud {
  const XY *pts;
  size_t n;
  size_t kdtree_get_point_count() const { return n; }
  double kdtree_get_pt(const uint32_t idx, const size_t dim) const {
    return dim == 0 ? pts[idx].x_mm : pts[idx].y_mm;
  }
  template <class BBox>
  bool kdtree_get_bbox(BBox &) const {
    return false;  // let nanoflann compute it
  }
};

using Metric = nanoflann::L2_Simple_Adaptor<double, LayerCloud, double, uint32_t>;
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<Metric, LayerCloud, 2, uint32_t>;

// Collects the unhandled points of the square |dx|,|dy| <= half around a
// centre into a caller buffer. nanoflann searches a disc (squared L2), so we
// ask for the circumscribed disc and filter to the square ourselves; this
// replaces radiusSearch, whose result set grows a std::vector.
class SquareResultSet {
 public:
  SquareResultSet(const XY *pts, const uint8_t *state, double cx, double cy,
                  double half_mm, uint32_t *out, size_t cap)
      : pts_(pts), state_(state), cx_(cx), cy_(cy), half_(half_mm),
        // A corner point sits exactly on the disc and nanoflann tests with a
        // strict '<': widen a hair; the square test below is the exact one.
        radius_sq_(2.0 * half_mm * half_mm * (1.0 + 1e-9) + 1e-12),
        out_(out), cap_(cap) {}

  size_t size() const { return count_; }
  bool full() const { return true; }
  double worstDist() const { return radius_sq_; }

  bool addPoint(double /*dist_sq*/, uint32_t idx) {
    if (state_[idx] != kUnhandled) return true;
    if (std::fabs(pts_[idx].x_mm - cx_) > half_) return true;
    if (std::fabs(pts_[idx].y_mm - cy_) > half_) return true;
    if (count_ == cap_) return false;  // cannot happen with cap = n; stop safely
    out_[count_++] = idx;
    return true;
  }

 private:
  const XY *pts_;
  const uint8_t *state_;
  double cx_, cy_, half_, radius_sq_;
  uint32_t *out_;
  size_t cap_;
  size_t count_ = 0;
};

bool less_xy(const XY &a, const XY &b) {
  if (a.x_mm != b.x_mm) return a.x_mm < b.x_mm;
  return a.y_mm < b.y_mm;
}

uint32_t clamp_k(uint32_t k) {
  return std::min(std::max(k, uint32_t{1}), kMaxKnnK);
}

// Mean distance to the k nearest neighbours of point i (itself excluded).
// The query asks for k + 1 because the point finds itself at distance 0;
// summing all k + 1 distances and dividing by k drops exactly that zero,
// whichever of several duplicates the tree returned as "itself".
double mean_knn_dist_mm(const KdTree &tree, const XY &q, uint32_t k) {
  uint32_t idx[kMaxKnnK + 1];
  double dist_sq[kMaxKnnK + 1];
  nanoflann::KNNResultSet<double, uint32_t, uint32_t> rs(k + 1);
  rs.init(idx, dist_sq);
  const double query[2] = {q.x_mm, q.y_mm};
  tree.findNeighbors(rs, query, nanoflann::SearchParams());
  double sum = 0.0;
  // Results come sorted by distance, so the summation order is fixed.
  for (uint32_t j = 0; j < rs.size(); ++j) sum += std::sqrt(dist_sq[j]);
  return std::max(sum / static_cast<double>(k), kMinMeanDistMm);
}

// Step 3.5.1 + 3.5.2: fills spacing_mm[i] with s_i.
void compute_spacing(const KdTree &tree, const XY *pts, size_t n, uint32_t k,
                     double s0_mm, double *spacing_mm) {
  double rho_min = std::numeric_limits<double>::infinity();
  double rho_max = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double rho = 1.0 / mean_knn_dist_mm(tree, pts[i], k);
    spacing_mm[i] = rho;  // hold rho until the extremes are known
    rho_min = std::min(rho_min, rho);
    rho_max = std::max(rho_max, rho);
  }
  for (size_t i = 0; i < n; ++i)
    spacing_mm[i] = spacing_from_density(spacing_mm[i], rho_min, rho_max, s0_mm);
}

// Of the candidates of one square, the one nearest their centroid; ties go
// to the lower canonical index so the choice never depends on tree order.
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
    const double dx = pts[cand[j]].x_mm - cx;
    const double dy = pts[cand[j]].y_mm - cy;
    const double d2 = dx * dx + dy * dy;
    if (d2 < best_d2 || (d2 == best_d2 && cand[j] < best)) {
      best_d2 = d2;
      best = cand[j];
    }
  }
  return best;
}

// Step 3.5.3: local-grid optimal sampling, marks ws.state.
void sample_cells(const KdTree &tree, const XY *pts, size_t n, const Workspace &ws) {
  std::fill(ws.state, ws.state + n, uint8_t{kUnhandled});
  for (size_t i = 0; i < n; ++i) {
    if (ws.state[i] != kUnhandled) continue;
    SquareResultSet rs(pts, ws.state, pts[i].x_mm, pts[i].y_mm,
                       0.5 * ws.spacing_mm[i], ws.candidates, n);
    const double query[2] = {pts[i].x_mm, pts[i].y_mm};
    tree.findNeighbors(rs, query, nanoflann::SearchParams());
    size_t m = rs.size();
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

}  // namespace

size_t workspace_bytes_per_point() {
  return sizeof(double) + sizeof(uint8_t) + sizeof(uint32_t);
}

size_t workspace_bytes(size_t n) {
  // Slack for aligning the double and uint32 arrays inside an arbitrary block.
  return n * workspace_bytes_per_point() + alignof(double) + alignof(uint32_t);
}

bool make_workspace(void *block, size_t block_bytes, size_t n, Workspace *ws) {
  if (block == nullptr || ws == nullptr || block_bytes < workspace_bytes(n)) return false;
  uintptr_t p = reinterpret_cast<uintptr_t>(block);
  p = (p + alignof(double) - 1) & ~static_cast<uintptr_t>(alignof(double) - 1);
  double *spacing = reinterpret_cast<double *>(p);
  p += n * sizeof(double);  // still aligned for uint32_t
  uint32_t *cand = reinterpret_cast<uint32_t *>(p);
  p += n * sizeof(uint32_t);
  ws->spacing_mm = spacing;
  ws->candidates = cand;
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

size_t thin_layer(XY *pts, size_t n, const Params &p, const Workspace &ws) {
  if (pts == nullptr || n == 0) return 0;
  if (ws.spacing_mm == nullptr || ws.state == nullptr || ws.candidates == nullptr ||
      ws.capacity < n || n > UINT32_MAX)
    return n;
  n = canonicalize(pts, n);
  const uint32_t k = clamp_k(p.knn_k);
  if (n < static_cast<size_t>(k) + 1 || !(p.s0_mm > 0.0)) return n;

  const LayerCloud cloud{pts, n};
  const KdTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  compute_spacing(tree, pts, n, k, p.s0_mm, ws.spacing_mm);
  sample_cells(tree, pts, n, ws);
  return compact_kept(pts, n, ws.state);
}

}  // namespace thinning
}  // namespace pv
