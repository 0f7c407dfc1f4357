// Plane fitting for levelling: RANSAC (paper Algorithm 1) and a
// least-squares refinement on the RANSAC inliers.
#ifndef PV_LEVELLING_PLANE_FIT_H
#define PV_LEVELLING_PLANE_FIT_H

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

namespace pv::levelling {

// n . p + d = 0 with |n| = 1.
struct Plane {
  Eigen::Vector3d n{0, 0, 1};
  double d = 0;
  double distance(const Eigen::Vector3d &p) const { return n.dot(p) + d; }
};

struct RansacParams {
  uint32_t iterations = 256;
  double tol_mm = 2.0;        // d_max: inlier distance
  uint64_t seed = 0x5eed;     // fixed: the same input gives the same plane
};

// Best plane through three of the points by inlier count (ties: the first
// found, so the outcome is deterministic). Returns the inlier count, 0 if
// fewer than 3 points or every triple was degenerate.
// soa: optional scratch of soa_cap doubles; with 3 n of them the points are
// counted from a copy by coordinate (x..., y..., z...), a loop without
// shuffles, with the same arithmetic: the same planes.
uint32_t ransac_plane(const Eigen::Vector3d *pts, size_t n,
                      const RansacParams &p, Plane *out, double *soa = nullptr,
                      size_t soa_cap = 0);

// Total least squares plane (smallest eigenvector of the covariance) of the
// points within tol_mm of *plane; replaces *plane. Returns the number of
// points used; leaves *plane unchanged and returns 0 if fewer than 3.
uint32_t refine_plane(const Eigen::Vector3d *pts, size_t n, double tol_mm,
                      Plane *plane);

// The plane of one surface within narrow_tol_mm: RANSAC at p.tol_mm, least
// squares within it, then within narrow_tol_mm. Two parallel surfaces closer
// than p.tol_mm (a floor scanned twice, registered a few mm apart) pass the
// wide band together and give a plane between them, near which the narrow
// band finds nothing; then RANSAC runs again at narrow_tol_mm and the
// plane is the denser surface's. Returns the points of the narrow fit, 0
// if no plane (then *out is undefined).
uint32_t fit_surface_plane(const Eigen::Vector3d *pts, size_t n, const RansacParams &p,
                           double narrow_tol_mm, Plane *out, double *soa = nullptr,
                           size_t soa_cap = 0);

}  // namespace pv::levelling

#endif
