// Cross-section area of one layer (Han et al. 2026, section 4.1).
//
// Method: split the layer's points at y_mid = (max y + min y) / 2 into an
// upper and a lower half, sort each half by x, fit y(x) piecewise with cubic
// least squares (normal equations X^T X a = X^T y), integrate every piece
// exactly, and return S = |S_up - S_low|.
//
// Decisions (copied into docs/method.md):
//
// D1 Breakpoints. P = max_pieces (default 16) pieces with breakpoints at
//    x_k = cx + R cos(theta_k), theta_k = pi k / P, cx = (min x + max x) / 2,
//    R = (max x - min x) / 2. Equal steps in angle give pieces that narrow
//    toward the ends, where a closed contour has vertical tangents and y(x)
//    behaves like sqrt(x - x_end), which one cubic over a wide interval cannot
//    follow. On a circle each piece then holds the same number of points.
//    Both halves use the same breakpoints.
//
// D2 Piece count follows point density. P = min(max_pieces,
//    (points in the thinner half) / target_points_per_piece (default 24)),
//    at least 1. Measured on random samplings (0.1 mm noise, 40 seeds): with
//    ~6 points per piece an end piece occasionally extrapolates wildly
//    (errors of 10-100 % on 100-150 point layers); 24 points per piece keeps
//    layers of >= 300 points within ~0.4 % worst case and 1000+ points within
//    ~0.03 %. Then any piece with fewer than min_points_per_piece (default 6,
//    never below 4 = number of cubic coefficients) points is merged with the
//    neighbour holding fewer points (left on ties), smallest first, so
//    clustered sampling degrades to wider pieces instead of failing. If a half
//    has fewer points than that, fit_area() returns false.
//
// D3 The half is covered from min x to max x without gaps. Each piece's
//    cubic is integrated over the x-range of its own points, as the paper's
//    (21) does, extended to the piece's interval when the strip left
//    uncovered is small (at most 3 point spacings or 3 mm: there a cubic
//    follows a convex contour better than a chord, which read 0.02-0.5 %
//    low), else by two spacings; the spans no piece supports are closed by
//    chords between
//    the neighbouring fits: the small strips between pieces (the paper
//    leaves these out, losing area in proportion to point spacing) and any
//    stretch of contour the scan did not see. Integrating a cubic over a
//    whole breakpoint interval instead extrapolates it across such a gap,
//    where it can run away: on an undercut (over-excavation) seen from
//    above, that gave areas of 10^6 mm^2 for a 4*10^4 mm^2 section.
//
// D4 How the halves meet at the ends. The x-extreme points (every point at
//    min x or max x) go into both halves, so both fits are anchored at the
//    same end points. We do NOT share a band of points around the split line
//    (mid_band_ratio, default 0): measured, a 2 % band biases the area by
//    -1e-4 (circle) to -9e-4 (bumpy contour), because the shared points lie on
//    the other half's branch of the end cap and pull each fit inward.
//
// D5 Conditioning. Each piece is solved in a centred, scaled variable
//    t = (x - xc) / hw in [-1, 1] (xc, hw: centre and half-width of the piece
//    interval) with y measured from y_mid. A raw monomial basis in x at
//    x ~ 500 mm would make X^T X span ~1e16 and lose every digit of the fit in
//    double; in t the normal matrix is O(1). The integral in t is exact:
//    hw * (2 a0 + 2 a2 / 3). Measuring y from y_mid changes S_up and S_low by
//    the same amount (both span [min x, max x]), so S is unchanged.
//
// D6 Rank-deficient pieces (all points at one x, say) fall back to the
//    highest degree (3, 2, 1, 0) whose LDLT pivots stay above 1e-10 of the
//    largest, so a degenerate piece never produces NaN.
//
// D7 Order independence and determinism. Each half is sorted by (x, y), a
//    total order, so any permutation of the input gives the same sorted
//    arrays and the same bits out. Non-finite input returns false.
//
// D8 Split line. Default: the paper's horizontal line y = y_mid. Option
//    split_through_extremes: the chord through the two x-extreme points. Why
//    the option exists: y(x) must be single-valued on each half, and a contour
//    whose x-extreme point sits away from y_mid folds back near the ends; the
//    fit then averages the two branches of the fold. Measured on
//    r = 110 + 4 sin(5 theta) (x-extreme point ~20 mm above y_mid; 2000-3000
//    points, 0.1 mm noise): y_mid split -3.6e-4 mean error, chord split
//    -1.3e-5. On a circle or ellipse both are identical in expectation.
//
// D9 An area larger than the bounding box of the layer's points is refused
//    (fit_area returns false): no closed contour through the points can
//    enclose more, so such a value is a failed fit, never a measurement.
#ifndef PV_AREA_AREA_FIT_H
#define PV_AREA_AREA_FIT_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv {
namespace area {

// Hard upper bound on pieces per half; the breakpoint tables live on the stack.
constexpr uint32_t kMaxPieces = 64;

struct Params {
  uint32_t max_pieces = 16;           // pieces per half before merging (D1), 1..kMaxPieces
  uint32_t min_points_per_piece = 6;  // merge threshold (D2), clamped to >= 4
  uint32_t target_points_per_piece = 24;  // pieces = min(max_pieces, half points / this) (D2)
  double mid_band_ratio = 0.0;        // extra shared band around the split, fraction of y extent (D4)
  bool split_through_extremes = false;  // chord split instead of y_mid (D8)
};

struct Result {
  double area_mm2 = 0.0;
  uint32_t pieces_upper = 0;  // pieces actually fitted after merging
  uint32_t pieces_lower = 0;
};

// Scratch (in XY elements) fit_area() needs for n points: both halves, with
// the shared band counted twice at most.
size_t scratch_needed(size_t n);

// Area enclosed by the layer contour sampled by pts[0..n).
// scratch: caller-owned, scratch_cap elements. Returns false (and leaves *out
// untouched) when the layer cannot support a fit (fewer than
// min_points_per_piece points in a half, zero extent, non-finite input),
// when scratch_cap < scratch_needed(n), or when pts/out is null.
bool fit_area(const XY *pts, size_t n, const Params &p, XY *scratch, size_t scratch_cap,
              Result *out);

}  // namespace area
}  // namespace pv

#endif
