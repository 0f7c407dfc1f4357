#include "levelling/levelling.h"

#include <algorithm>
#include <cmath>

#include "levelling/plane_fit.h"
#include "levelling/rodrigues.h"

namespace pv::levelling {

namespace {

constexpr double kPi = 3.14159265358979323846;

double quantile(double *v, size_t n, double q) {
  const size_t k = std::min(n - 1, size_t(q * double(n - 1) + 0.5));
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

// Share of a slab's points that lie near the cloud's axis: a floor (disc)
// has some, the opening (a ring of wall or ground) has almost none.
double axis_occupancy(const Eigen::Vector3d *pts, size_t n, double z_from,
                      double z_to, double *v) {
  double cx = 0, cy = 0;
  for (size_t i = 0; i < n; ++i) {
    cx += pts[i].x();
    cy += pts[i].y();
  }
  cx /= double(n);
  cy /= double(n);
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    if (pts[i].z() >= z_from && pts[i].z() <= z_to) {
      v[m++] = std::hypot(pts[i].x() - cx, pts[i].y() - cy);
    }
  }
  if (m < 8) return 0.0;
  const double r_med = quantile(v, m, 0.5);
  size_t inner = 0;
  for (size_t i = 0; i < m; ++i) inner += v[i] < 0.5 * r_med;
  return double(inner) / double(m);
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
  const double c = std::clamp(R(2, 2), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

Status estimate(const P3 *pts, size_t n, const Params &p, const Scratch &s,
                Transform *out, Report *report) {
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

  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Plane plane;
  for (uint32_t round = 0; round < p.max_rounds; ++round) {
    rotate_all(R, s.a, n, s.b);
    const ZRange zr = robust_z_range(s.b, n, s.v);
    const double z_th = zr.lo + p.bottom_band_ratio * (zr.hi - zr.lo);
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
      if (s.b[i].z() < z_th) s.c[m++] = s.b[i];
    }
    report->candidates = uint32_t(m);
    if (m < 3) return Status::NoPlane;
    if (ransac_plane(s.c, m, rp, &plane) < 3) return Status::NoPlane;
    refine_plane(s.c, m, rp.tol_mm, &plane);
    const uint32_t used = refine_plane(s.c, m, p.refine_tol_mm, &plane);
    if (used < 3) return Status::NoPlane;
    report->inliers = used;

    // Most of the pit lies on the positive side of its bottom plane.
    size_t above = 0;
    for (size_t i = 0; i < n; ++i) above += plane.distance(s.b[i]) > 0;
    if (2 * above < n) {
      plane.n = -plane.n;
      plane.d = -plane.d;
    }
    const Eigen::Matrix3d step = rotation_onto_z(plane.n);
    const double moved_deg =
        std::acos(std::clamp(plane.n.z(), -1.0, 1.0)) * 180.0 / kPi;
    R = step * R;
    report->rounds = round + 1;

    if (round == 0) {
      rotate_all(R, s.a, n, s.b);
      const ZRange z = robust_z_range(s.b, n, s.v);
      const double band = p.bottom_band_ratio * (z.hi - z.lo);
      const double low = axis_occupancy(s.b, n, z.lo, z.lo + band, s.v);
      const double high = axis_occupancy(s.b, n, z.hi - band, z.hi, s.v);
      if (high > low) {  // the plane found was the opening: turn over
        R = half_turn_x() * R;
        report->flipped = true;
        continue;
      }
    }
    if (round > 0 && moved_deg < 1e-4) break;
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
  if (ransac_plane(s.c, z_count, rp, &flat) < 3) return Status::NoPlane;
  refine_plane(s.c, z_count, rp.tol_mm, &flat);
  refine_plane(s.c, z_count, p.refine_tol_mm, &flat);
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
