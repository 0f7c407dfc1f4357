// Rim (top edge) height: the upper integration limit (paper 3.3).
//
// The paper finds edge points (Y-extremes per X interval in the top 20 % of
// z) and interpolates a synthetic lid between them; the lid's purpose is the
// upper integration limit. We determine that limit directly, in two ways
// (docs/method.md says why):
// - Ground around the rim: the ground is a horizontal surface, a sharp peak
//   in the z-histogram of the top band of the levelled sample. The rim
//   height is the median z of the points in that peak.
// - No ground (a scan of the walls only): the walls stop at the rim. The
//   wall top is where the per-layer point weight falls off; the fraction of
//   the last layer that is occupied gives the height to a fraction of a
//   layer.
#ifndef PV_RIM_RIM_H
#define PV_RIM_RIM_H

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "gridding/gridding.h"

namespace pv::rim {

struct Params {
  double band_ratio = 0.2;        // top candidates: top 20 % of the z-range
  double peak_window_mm = 1.0;    // width of the ground peak window
  double ground_share = 0.25;     // share of the band a ground peak must hold
  double top_quantile = 0.98;     // the band's top: this height quantile (rim.cpp)
};

struct Ground {
  bool found = false;
  double z_mm = 0;
  uint32_t points = 0;
};

// pts: levelled sample (bottom at z = 0). scratch: n doubles.
Ground detect_ground(const Eigen::Vector3d *pts, size_t n, const Params &p,
                     double *scratch);

// The ground around the rim as a plane (method surface): levelling on the
// floor leaves the ground tilted where the floor is not level (a bowl, an
// uneven hand-dug floor), and the volume is defined below the ground.
// Deterministic RANSAC (fixed sequence) on the top band of the levelled
// sample, then least squares on the inliers. Found when the plane holds
// ground_share of the band and is within 20 deg of horizontal (the levelling
// it corrects can be 12 deg off on a bowl).
struct GroundPlane {
  bool found = false;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // upward
  double d = 0;           // plane: normal . p = d
  uint32_t inliers = 0;
};
GroundPlane fit_ground_plane(const Eigen::Vector3d *pts, size_t n, const Params &p,
                             double *scratch, uint32_t *index_scratch);

// weight[j]: points per final layer j, each stored point counted with the
// thinning factor of its bin. Returns the wall-top height, or a negative
// value if no run of wall layers is found, or if the wall fades out above
// it instead of ending (no top edge was scanned).
double wall_top_mm(const double *weight, const gridding::Grid &grid,
                   double *scratch);

}  // namespace pv::rim

#endif
