#include "levelling/levelling.h"

#include <algorithm>
#include <cmath>

#include "common/angle.h"
#include "levelling/plane_fit.h"
#include "levelling/rodrigues.h"

namespace pv::levelling {

namespace {

constexpr double kPi = 3.14159265358979323846;

double quantile(double *v, size_t n, double q) {
  // Round half up of a non-negative index: the cast is exact here, and no libm call.
  const size_t k = std::min(n - 1, size_t(q * double(n - 1) + 0.5));  // NOLINT(bugprone-incorrect-roundings)
  std::nth_element(v, v + k, v + n);
  return v[k];
}

struct ZRange {
  double lo, hi;
};

ZRange robust_z_range(const Eigen::Vector3d *pts, size_t n, double *v) {
  for (size_t i = 0; i < n; ++i) v[i] = pts[i].z();
  const double lo = quantile(v, n, 0.001);
  const double hi = quantile(v, n, 0.999);
  return {lo, hi};
}

double bbox_diagonal(const Eigen::Vector3d *pts, size_t n) {
  Eigen::Vector3d lo = pts[0], hi = pts[0];
  for (size_t i = 1; i < n; ++i) {
    lo = lo.cwiseMin(pts[i]);
    hi = hi.cwiseMax(pts[i]);
  }
  return (hi - lo).norm();
}

// Points of a thin slab that lie near the cloud's axis. The floor is a dense
// surface across the axis; the opening is a hole (a ring of wall top or of
// ground), crossed only by sparse multipath points. Absolute counts, not
// shares: a share is fooled when multipath crowds a sparse opening.
size_t axis_count(const Eigen::Vector3d *pts, size_t n, double z_from, double z_to,
                  double *v) {
  double cx = 0, cy = 0;
  for (size_t i = 0; i < n; ++i) {
    cx += pts[i].x();
    cy += pts[i].y();
  }
  cx /= double(n);
  cy /= double(n);
  // The radius by a square root (IEEE: rounded alike everywhere), not
  // std::hypot, a libm function that need not round alike on every target.
  const auto radius = [&](size_t i) {
    const double dx = pts[i].x() - cx, dy = pts[i].y() - cy;
    return std::sqrt(dx * dx + dy * dy);
  };
  for (size_t i = 0; i < n; ++i) v[i] = radius(i);
  const double r_near = 0.5 * quantile(v, n, 0.5);
  size_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    const double r = radius(i);
    count += pts[i].z() >= z_from && pts[i].z() <= z_to && r < r_near;
  }
  return count;
}

void rotate_all(const Eigen::Matrix3d &R, const Eigen::Vector3d *in, size_t n,
                Eigen::Vector3d *out) {
  for (size_t i = 0; i < n; ++i) out[i] = R * in[i];
}

Eigen::Matrix3d half_turn_x() {
  Eigen::Matrix3d f;
  f << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  return f;
}

}  // namespace

double Transform::tilt_deg() const {
  return angle_of_cos(R(2, 2)) * 180.0 / kPi;
}

namespace {

// The paper's fit, iterated from a starting orientation R: bottom candidates
// in the current frame, RANSAC, least squares; rotate; repeat until the
// normal stops moving. Returns false if no plane was found.
bool converge(const Eigen::Vector3d *a, size_t n, const Params &p, const RansacParams &rp,
              const Scratch &s, Eigen::Matrix3d *R, Report *report) {
  Plane plane;
  for (uint32_t round = 0; round < p.max_rounds; ++round) {
    rotate_all(*R, a, n, s.b);
    const ZRange zr = robust_z_range(s.b, n, s.v);
    const double z_th = zr.lo + p.bottom_band_ratio * (zr.hi - zr.lo);
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
      if (s.b[i].z() < z_th) s.c[m++] = s.b[i];
    }
    report->candidates = uint32_t(m);
    if (m < 3) return false;
    const uint32_t used = fit_surface_plane(s.c, m, rp, p.refine_tol_mm, &plane, s.v, n);
    if (used < 3) return false;
    report->inliers = used;
    // Most of the pit lies on the positive side of its bottom plane.
    size_t above = 0;
    for (size_t i = 0; i < n; ++i) above += plane.distance(s.b[i]) > 0;
    if (2 * above < n) {
      plane.n = -plane.n;
      plane.d = -plane.d;
    }
    const double moved_deg = angle_of_cos(plane.n.z()) * 180.0 / kPi;
    *R = rotation_onto_z(plane.n) * *R;
    report->rounds = round + 1;
    if (round > 0 && moved_deg < 1e-4) break;
  }
  return true;
}

// How floor-like the low end of the frame R is (see axis_count).
size_t floor_score(const Eigen::Vector3d *a, size_t n, const Eigen::Matrix3d &R, double slab_mm,
                   const Scratch &s) {
  rotate_all(R, a, n, s.b);
  const ZRange z = robust_z_range(s.b, n, s.v);
  return axis_count(s.b, n, z.lo - slab_mm, z.lo + slab_mm, s.v);
}

// Starts from both ends of the scanner's Z: a scan may be upside down, and
// from the wrong end the fit can settle on the opening or a wall. Keeps the
// result whose low end is most like a floor.
bool best_of_both_ends(const Eigen::Vector3d *a, size_t n, const Params &p,
                       const RansacParams &rp, const Scratch &s, Eigen::Matrix3d *R,
                       Report *report) {
  Eigen::Matrix3d R_up = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R_down = half_turn_x();
  Report rep_up, rep_down;
  const bool ok_up = converge(a, n, p, rp, s, &R_up, &rep_up);
  const bool ok_down = converge(a, n, p, rp, s, &R_down, &rep_down);
  if (!ok_up && !ok_down) return false;
  const double slab = 2.0 * rp.tol_mm;
  const size_t score_up = ok_up ? floor_score(a, n, R_up, slab, s) : 0;
  const size_t score_down = ok_down ? floor_score(a, n, R_down, slab, s) : 0;
  const bool use_up = ok_up && (!ok_down || score_up >= score_down);
  *R = use_up ? R_up : R_down;
  *report = use_up ? rep_up : rep_down;
  report->flipped = !use_up;
  return true;
}

}  // namespace

Status estimate(const P3 *pts, size_t n, const Params &p, const Scratch &s,
                Transform *out, Report *report, const Eigen::Matrix3d *start) {
  *report = Report{};
  if (n < kMinPoints) return Status::TooFewPoints;

  // Work about the centroid: keeps the numbers small and puts the pit axis
  // near x = y = 0 after levelling.
  Eigen::Vector3d c0 = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) c0 += Eigen::Vector3d(pts[i].x_mm, pts[i].y_mm, pts[i].z_mm);
  c0 /= double(n);
  for (size_t i = 0; i < n; ++i) {
    s.a[i] = Eigen::Vector3d(pts[i].x_mm, pts[i].y_mm, pts[i].z_mm) - c0;
  }

  const double extent = bbox_diagonal(s.a, n);
  RansacParams rp;
  rp.iterations = p.ransac_iterations;
  rp.tol_mm = p.plane_tol_ratio * extent;
  Eigen::Matrix3d R;
  if (start != nullptr) {
    R = *start;
    if (!converge(s.a, n, p, rp, s, &R, report)) return Status::NoPlane;
  } else if (!best_of_both_ends(s.a, n, p, rp, s, &R, report)) {
    return Status::NoPlane;
  }


  // Translation: the bottom plane at z = 0. Evaluate the final plane height
  // in the final frame from the final inliers.
  rotate_all(R, s.a, n, s.b);
  const ZRange zr = robust_z_range(s.b, n, s.v);
  const double z_th = zr.lo + p.bottom_band_ratio * (zr.hi - zr.lo);
  double z_sum = 0;
  size_t z_count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (s.b[i].z() < z_th) s.c[z_count++] = s.b[i];
  }
  Plane flat;  // horizontal by construction after the last rotation
  if (fit_surface_plane(s.c, z_count, rp, p.refine_tol_mm, &flat, s.v, n) < 3) {
    return Status::NoPlane;
  }
  z_count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (std::fabs(flat.distance(s.b[i])) <= p.refine_tol_mm) {
      z_sum += s.b[i].z();
      ++z_count;
    }
  }
  if (z_count < 3) return Status::NoPlane;
  const double z_bottom = z_sum / double(z_count);

  out->R = R;
  out->t = -(R * c0) - Eigen::Vector3d(0, 0, z_bottom);
  return Status::Ok;
}

}  // namespace pv::levelling
