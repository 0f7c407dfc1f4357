// Pose normalisation (paper 3.2): find the pit bottom plane and the rigid
// transform that makes it horizontal at z = 0 with the pit opening upward.
//
// Runs on the order-independent hash sample, so the same scan gives the same
// transform whatever the order of its points. No allocation: the caller
// passes the scratch arrays (scratch_points() entries each).
//
// Decisions (docs/method.md):
// - Bottom candidates are the points within beta of the z-range above the
//   lowest z (Algorithm 1), with z-range taken between the 0.1 % and 99.9 %
//   quantiles so that a few far strays cannot stretch it.
// - The paper assumes the scan is roughly upright. A handheld scan may be
//   tilted (up to ~30 deg) or upside down, so the fit is iterated: the plane
//   found in one round levels the next round's candidates, until the normal
//   moves by less than 1e-4 deg. Each round: RANSAC (d_max = alpha * extent),
//   then total least squares on the inliers, then again within refine_tol_mm.
// - Which way is up: the iterated fit runs twice, starting from scanner +Z
//   and from -Z (an upside-down or steeply tilted scan can lead the fit from
//   one end onto the opening or a wall). In each round the normal is
//   oriented so that most points lie on its positive side. Of the two
//   results, the one whose low end has more points near the axis in a thin
//   slab wins: a floor is a dense surface across the axis, the opening a
//   ring (wall top or ground) crossed only by sparse multipath points.
#ifndef PV_LEVELLING_LEVELLING_H
#define PV_LEVELLING_LEVELLING_H

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv::levelling {

struct Params {
  double bottom_band_ratio = 0.05;  // beta
  double plane_tol_ratio = 0.005;   // alpha
  uint32_t ransac_iterations = 256;
  double refine_tol_mm = 0.6;       // final least-squares band
  uint32_t max_rounds = 6;
};

// p_levelled = R * p_raw + t
struct Transform {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const P3 &p) const {
    return R * Eigen::Vector3d(p.x_mm, p.y_mm, p.z_mm) + t;
  }
  double level_z(const P3 &p) const {
    return R(2, 0) * p.x_mm + R(2, 1) * p.y_mm + R(2, 2) * p.z_mm + t.z();
  }
  // Angle between the scanner's +Z and the pit's up axis (180 = upside down).
  double tilt_deg() const;
};

enum class Status { Ok, TooFewPoints, NoPlane };

struct Report {
  uint32_t candidates = 0;     // bottom candidates in the last round
  uint32_t inliers = 0;        // of the final least-squares fit
  uint32_t rounds = 0;
  bool flipped = false;        // the fit from scanner -Z won
};

struct Scratch {
  Eigen::Vector3d *a;  // each: at least n entries
  Eigen::Vector3d *b;
  Eigen::Vector3d *c;
  double *v;
};

constexpr uint32_t kMinPoints = 64;

// start: NULL for the full fit (from both ends, see above). A previous
// rotation to refine from instead: one start, fewer rounds. The session uses
// it for its provisional refinements only; the final fit is always the full
// one, so the result does not depend on when refinements happened.
Status estimate(const P3 *pts, size_t n, const Params &p, const Scratch &s,
                Transform *out, Report *report, const Eigen::Matrix3d *start = nullptr);

}  // namespace pv::levelling

#endif
