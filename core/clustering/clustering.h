// Per-layer clustering (Han et al. 2026, section 3.6): decide whether a
// thinned layer is a near-circular or a crescent-shaped section, then keep
// only the points of its contour band, dropping stray points inside and
// outside the wall.
//
//   classify: crescent if ANY of  elongation > crescent_range_mm (50),
//                                 dy_x > crescent_cross_mm (80),
//                                 dx_y > crescent_cross_mm (80);
//             otherwise near-circular.
//   near-circular: centre O = centre of the XY bounding box, d_i = |p_i - O|,
//             r_base = max d_i, keep d_i in [r_base - 20, r_base + 20].
//   crescent: centre O_d = centroid, polar angle theta_i and radius dd_i
//             about it; among the points inside the angle window, the 10 % and
//             90 % quantiles d_low, d_up of dd_i; keep the points inside the
//             angle window with dd_i in [d_low - 10, d_up + 10].
//
// Decisions (copied into docs/method.md):
//  * "range" (the paper's "extreme range difference of the XY coordinates"):
//    taken literally as the XY extent it exceeds 50 mm for every real pit
//    (they are ~220 mm across), so every layer would be a crescent. We read
//    it as the elongation |x_range - y_range|: 0 for a circle, 100 mm for a
//    200 x 100 mm ellipse, large for a one-sided arc.
//  * "Y range at the maximum X" (dy_x) / "X range at the maximum Y" (dx_y):
//    the Y (X) extent of the points within a strip of cross_strip_mm = 1 mm
//    of the maximum X (Y). A single point has no range; the strip makes the
//    test see the whole "tip" of the section. On a closed r = 110 mm circle
//    the strip holds a chord of ~30 mm (< 80); a C-shaped arc open towards
//    +X has both horns in the strip (dy_x ~ 2r), which is what the test is
//    for.
//  * Near-circular centre and r_base: the paper's literal rule (bounding box
//    centre, r_base = max distance) is the default. Known weakness, measured
//    in test_clustering: a single stray point outside the wall becomes r_base
//    and the band [r_base - 20, r_base + 20] then drops the whole wall. The
//    knob circle_rbase_quantile (1.0 = max = paper) lets the lead switch to a
//    robust r_base (e.g. 0.5 = median distance) if the corpus says so.
//  * Crescent angle window: our copy of the paper prints "[pi/2, pi]", a
//    fixed quadrant in the scanner frame. It can only be right for the
//    paper's own fixture orientation: on a pit scanned in any other
//    orientation it would delete real wall. Default window = all angles
//    [-pi, pi] (no angular cut; the radius band does the cleaning); the
//    literal paper window is available as crescent_angle_min/max_rad =
//    pi/2, pi. The quantiles are taken over the points inside the window, as
//    in the paper. Angles are atan2 in (-pi, pi], the window is inclusive.
//  * Crescent "centre of the dense crescent area": the centroid of the layer's
//    points (after thinning the density is roughly even, so the centroid is
//    the centre of the crescent's mass).
//  * Quantiles: linear interpolation between order statistics (h = q (m-1)).
//  * Order independence: the layer is first put in canonical (x, y) order
//    (non-finite points dropped, -0.0 -> +0.0; see thinning::canonicalize):
//    sums such as the centroid then add up in one fixed order. The kept
//    points come out in that canonical order, compacted to the front.
//  * Scratch: the quantiles need scratch_cap >= n doubles (8 bytes/point).
//    The paper's default near-circular path (quantile 1.0) needs none. If
//    the scratch is needed but too small, nothing is removed (never lose a
//    wall because of a sizing bug) and info->r_low_mm/r_high_mm are 0/inf.
#ifndef PV_CLUSTERING_CLUSTERING_H
#define PV_CLUSTERING_CLUSTERING_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv {
namespace clustering {

struct Params {
  double crescent_range_mm = 50;   // elongation |x_range - y_range| above which: crescent
  double crescent_cross_mm = 80;   // dy_x or dx_y above which: crescent
  double circle_band_mm = 20;      // near-circular band half-width around r_base
  double crescent_relax_mm = 10;   // crescent radius band relaxation
  double cross_strip_mm = 1.0;     // strip width that defines "at max X / max Y"
  double circle_rbase_quantile = 1.0;  // 1.0 = max distance (paper); 0.5 = median
  double crescent_q_low = 0.10;    // lower radius quantile (paper)
  double crescent_q_high = 0.90;   // upper radius quantile (paper)
  double crescent_angle_min_rad = -3.14159265358979323846;  // paper literal: pi/2
  double crescent_angle_max_rad = 3.14159265358979323846;   // paper literal: pi
};

enum class Shape : uint8_t { NearCircular = 0, Crescent = 1 };

struct Info {
  Shape shape = Shape::NearCircular;
  double center_x_mm = 0;  // bbox centre (near-circular) or centroid (crescent)
  double center_y_mm = 0;
  double r_base_mm = 0;    // near-circular: reference radius; crescent: d_up
  double r_low_mm = 0;     // radius band actually applied (inclusive)
  double r_high_mm = 0;
};

// The morphology figures the classification uses (exposed for tests/plots).
struct Morphology {
  double x_range_mm, y_range_mm;
  double elongation_mm;  // |x_range - y_range|
  double dy_x_mm;        // Y range of the points within cross_strip_mm of max X
  double dx_y_mm;        // X range of the points within cross_strip_mm of max Y
};

// Morphology and shape of a layer; any order of the points gives the same.
Morphology measure_morphology(const XY *pts, size_t n, const Params &p);
Shape classify(const Morphology &m, const Params &p);

// Clusters the layer in place: kept points are compacted to the front of
// pts in canonical (x, y) order, their count is returned; info (may be null)
// says what was decided. scratch: caller buffer of scratch_cap doubles, needs
// >= n when a quantile is used (crescent, or circle_rbase_quantile < 1).
size_t cluster_layer(XY *pts, size_t n, const Params &p, double *scratch,
                     size_t scratch_cap, Info *info);

}  // namespace clustering
}  // namespace pv

#endif
