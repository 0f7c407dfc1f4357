// Adaptive thinning of one Z-gridded layer (Han et al. 2026, section 3.5).
//
// A layer arrives with every point at the same z, so the whole stage works in
// 2-D on XY. Three steps, as in the paper:
//   3.5.1  d_i  = mean distance from point i to its k nearest neighbours,
//          rho_i = 1 / d_i.
//   3.5.2  s_i  = 0.5 s0 + (rho_i - rho_min) / (rho_max - rho_min) * 1.5 s0,
//          clamped to [0.5 s0, 2 s0]: dense places get a wide cell (strong
//          thinning), sparse places a narrow one (almost nothing removed).
//   3.5.3  visit the points in canonical order; for each point not yet
//          handled, take the axis-aligned square of side s_i centred on it,
//          gather the still-unhandled points inside (the point itself is one
//          of them), keep ONE and mark the others as sampled.
//
// Decisions (copied into docs/method.md):
//  * Which point of a square is kept. The paper keeps the candidate nearest
//    the "grid centre" and also speaks of "centroid constraints". The square
//    is centred on the visited point, so taken literally the visited point
//    (distance 0) would always win and the selection would be a no-op: the
//    output would simply be the lexicographically-first point of every cell,
//    i.e. whatever noisy sample happens to come first. We keep instead the
//    candidate nearest the CENTROID of the candidates in the square. The
//    centroid averages the range noise of all the candidates, so the kept
//    observation is the one that sits closest to the local mean surface: the
//    kept ring is less noisy than a random pick, while still being a real
//    measured point (no synthetic points, no smoothing across cells). Ties
//    (equal squared distance) go to the lower canonical index.
//  * s0 is in millimetres, default 1.0 mm, so the cell side runs from 0.5 mm
//    (sparsest place: about the scanner's point pitch, i.e. nothing there is
//    removed) to 2 mm (densest place). A 2 mm spacing still leaves ~350
//    points on a 220 mm pit contour, and the polygon through them misses the
//    circle by (c/r)^2/6 ~ 0.006 % in area: far below the 0.05 % budget,
//    while a dense layer of 20 000 points drops to a few hundred. The paper's
//    figures (3, 7, 14, no unit) are for its own scanner; the lead tunes s0
//    on the corpus.
//  * k default 8 (the paper gives no value): enough neighbours that one
//    duplicate or one stray point does not decide a density, few enough that
//    d_i stays local (8 neighbours of a 0.1 mm-pitch contour span ~0.4 mm).
//    k is clamped to [1, kMaxKnnK] because the kNN result lives in a fixed
//    array on the stack (no allocation per query).
//  * d_i is floored at kMinMeanDistMm (1e-6 mm) so exact duplicates (d_i = 0)
//    do not divide by zero; such a point just gets the densest spacing.
//  * rho_max == rho_min (perfectly uniform layer, or every point a duplicate):
//    the ratio is taken as 0, i.e. s_i = 0.5 s0 everywhere (the cautious end).
//  * A layer with n < k + 1 points has no k neighbours per point: it is kept
//    whole (sorted into canonical order). Such a layer is far too small for
//    the area fit anyway; thinning it would only lose information.
//  * Non-finite points (NaN / inf) are removed first: they would break the
//    strict ordering of the canonical sort and the neighbour grid.
//  * Order independence: the points are sorted lexicographically by (x, y)
//    (after turning -0.0 into +0.0) before anything else, so any permutation
//    of the same points gives the same bits out.
//
// Neighbour search: a hashed uniform grid over the layer, built per layer in
// the Workspace (counting sort of point indices by cell). It replaced a
// nanoflann kd-tree, which allocated per layer (index vector, node pool),
// throws, and so could not build for the MCU (no exceptions, no heap). The
// grid is exact: the kNN of a point are searched ring by ring of cells until
// no unvisited cell can hold a nearer point, and d_i is the sum of the k + 1
// smallest distances (the point itself included, at 0) taken in ascending
// order, divided by k: a function of the distance multiset only, so which of
// several equidistant points is "the k-th" cannot change a bit (the kd-tree
// gave the same d_i bit for bit). The square of step 3.5.3 gathers its
// candidates from the cells it overlaps and sorts them by canonical index
// before the centroid is summed, so the kept point does not depend on the
// search structure's visiting order either. Cell side: (w + h) (k + 1) / n
// for a w x h bounding box, about k + 1 points per cell along a contour;
// cell ids hash into a power-of-two table of at most n buckets.
//
// Memory: no heap allocation at all. The caller passes a Workspace with
// workspace_bytes_per_point() = 21 bytes per point (a double spacing, a
// state byte, a uint32 candidate index, a uint32 grid item and a uint32
// bucket start), plus one bucket start and alignment slack per block
// (workspace_bytes), carved from the session block.
#ifndef PV_THINNING_ADAPTIVE_THINNING_H
#define PV_THINNING_ADAPTIVE_THINNING_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv {
namespace thinning {

// The kNN result of one query lives in a fixed stack array of this size + 1.
constexpr uint32_t kMaxKnnK = 32;
// Floor of the mean kNN distance: exact duplicates must not give rho = inf.
constexpr double kMinMeanDistMm = 1e-6;

struct Params {
  uint32_t knn_k = 8;  // neighbours for the density estimate; clamped to [1, kMaxKnnK]
  double s0_mm = 1.0;  // base sampling interval; cells span [0.5 s0, 2 s0]
};

// Caller-owned scratch, each array with room for `capacity` points.
struct Workspace {
  double *spacing_mm = nullptr;   // s_i per point (also holds d_i on the way)
  uint8_t *state = nullptr;       // 0 = unhandled, 1 = kept, 2 = sampled away
  uint32_t *candidates = nullptr; // indices of the unhandled points of one square
  uint32_t *grid_items = nullptr; // point indices grouped by grid bucket
  uint32_t *grid_start = nullptr; // bucket b holds grid_items[start[b], start[b+1])
  size_t capacity = 0;
};

// Bytes of Workspace per point (21).
size_t workspace_bytes_per_point();
// Bytes of one raw block that make_workspace() can carve for n points
// (per-point bytes plus alignment slack).
size_t workspace_bytes(size_t n);
// Carves a Workspace for up to n points out of a caller block. Returns false
// (and leaves *ws untouched) when the block is too small or a pointer is null.
bool make_workspace(void *block, size_t block_bytes, size_t n, Workspace *ws);

// Thins the layer in place: the kept points are compacted to the front of
// pts in canonical (x, y) order and their count is returned. The rest of
// pts[0..n) is left in an unspecified order.
// If the workspace is missing or smaller than n, nothing is done and n is
// returned (points untouched): never lose data because of a sizing bug.
size_t thin_layer(XY *pts, size_t n, const Params &p, const Workspace &ws);

// Helpers, public for the tests and for the clustering stage.
// Removes non-finite points (compacting), normalises -0.0, sorts by (x, y).
// Returns the number of points that remain.
size_t canonicalize(XY *pts, size_t n);
// s_i from rho_i per the paper's mapping, clamped to [0.5 s0, 2 s0].
double spacing_from_density(double rho, double rho_min, double rho_max, double s0_mm);
// Step 3.5.1 alone, for the tests: d_i (floored at kMinMeanDistMm) of every
// point of pts[0..n), which must be canonical (see canonicalize), into
// d_mm[0..n), using ws's grid. False if ws is too small or n < k + 1.
bool mean_knn_distances(const XY *pts, size_t n, uint32_t k, const Workspace &ws, double *d_mm);

}  // namespace thinning
}  // namespace pv

#endif
