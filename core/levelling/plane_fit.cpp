#include "levelling/plane_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "common/point_hash.h"

namespace pv::levelling {

static bool plane_through(const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                          const Eigen::Vector3d &c, Plane *out) {
  Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  // Nearly collinear triples give a normal dominated by rounding.
  if (!(len > 1e-9 * (b - a).squaredNorm() + 1e-12)) return false;
  n /= len;
  out->n = n;
  out->d = -n.dot(a);
  return true;
}

// Points within tol of the plane n . p + d = 0, with Plane::distance's
// arithmetic as Eigen evaluates it (n.x x + (n.y y + n.z z), + d). A loop of
// its own, over separate arrays: GCC vectorises it (not inside the RANSAC
// loop nest).
static uint32_t count_within(const double *__restrict xs, const double *__restrict ys,
                             const double *__restrict zs, size_t n, double nx, double ny,
                             double nz, double d, double tol) {
  uint32_t c = 0;
  for (size_t q = 0; q < n; ++q) {
    const double dist = nx * xs[q] + (ny * ys[q] + nz * zs[q]) + d;
    if (std::fabs(dist) <= tol) ++c;  // this form vectorises (GCC 12), a select does not
  }
  return c;
}

// Points counted between two checks of whether a candidate can still win.
constexpr size_t kCountChunk = 512;

uint32_t ransac_plane(const Eigen::Vector3d *pts, size_t n,
                      const RansacParams &p, Plane *out, double *soa, size_t soa_cap) {
  if (n < 3 || n > UINT32_MAX) return 0;
  const bool by_coord = soa != nullptr && soa_cap / 3 >= n;
  double *xs = soa, *ys = soa + n, *zs = soa + 2 * n;
  if (by_coord) {
    for (size_t q = 0; q < n; ++q) {
      xs[q] = pts[q].x();
      ys[q] = pts[q].y();
      zs[q] = pts[q].z();
    }
  }
  SplitMix64 rng{p.seed};
  const auto count = uint32_t(n);
  uint32_t best = 0;
  for (uint32_t it = 0; it < p.iterations; ++it) {
    const uint32_t i = rng.below(count), j = rng.below(count), k = rng.below(count);
    if (i == j || j == k || i == k) continue;
    Plane cand;
    if (!plane_through(pts[i], pts[j], pts[k], &cand)) continue;
    // Counted in chunks, and given up once the points left cannot lift the
    // count above the best (a candidate replaces the best only when it has
    // more inliers): the same plane, the same count, at a fraction of the
    // work for the many candidates through an outlier.
    uint32_t inliers = 0;
    size_t done = 0;
    while (done < n && inliers + (n - done) > best) {
      const size_t m = std::min(kCountChunk, n - done);
      if (by_coord) {
        // Plane::distance as Eigen evaluates it: n.x x + (n.y y + n.z z), + d.
        const double nx = cand.n.x(), ny = cand.n.y(), nz = cand.n.z(), d = cand.d;
        inliers += count_within(xs + done, ys + done, zs + done, m, nx, ny, nz, d, p.tol_mm);
      } else {
        for (size_t q = done; q < done + m; ++q) {
          if (std::fabs(cand.distance(pts[q])) <= p.tol_mm) ++inliers;
        }
      }
      done += m;
    }
    if (done == n && inliers > best) {
      best = inliers;
      *out = cand;
    }
  }
  return best;
}

uint32_t refine_plane(const Eigen::Vector3d *pts, size_t n, double tol_mm,
                      Plane *plane) {
  // Two passes (mean, then covariance about the mean) for accuracy with
  // coordinates far from the origin.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  uint32_t used = 0;
  for (size_t q = 0; q < n; ++q) {
    if (std::fabs(plane->distance(pts[q])) <= tol_mm) {
      mean += pts[q];
      ++used;
    }
  }
  if (used < 3) return 0;
  mean /= double(used);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t q = 0; q < n; ++q) {
    if (std::fabs(plane->distance(pts[q])) <= tol_mm) {
      const Eigen::Vector3d e = pts[q] - mean;
      cov += e * e.transpose();
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d nrm = es.eigenvectors().col(0);  // smallest eigenvalue
  if (nrm.dot(plane->n) < 0) nrm = -nrm;            // keep the orientation
  plane->n = nrm;
  plane->d = -nrm.dot(mean);
  return used;
}

uint32_t fit_surface_plane(const Eigen::Vector3d *pts, size_t n, const RansacParams &p,
                           double narrow_tol_mm, Plane *out, double *soa, size_t soa_cap) {
  if (ransac_plane(pts, n, p, out, soa, soa_cap) < 3) return 0;
  refine_plane(pts, n, p.tol_mm, out);
  // One surface keeps most of the wide band's points in the narrow one (a
  // flat floor above 0.9 on the standard set, a bowl's curved bottom 0.09
  // to 0.23); a floor twice, 2 mm apart, 0 to 0.001. Only a narrow band
  // that found no plane at all (fewer than 3 points, where the fit failed)
  // is fitted again: every fit that succeeded keeps its plane, bit for bit
  // (a share of 1/20 as the test moved a fuzz finding's levelling,
  // test_sections_check).
  const uint32_t narrow = refine_plane(pts, n, narrow_tol_mm, out);
  if (narrow >= 3) return narrow;
  RansacParams q = p;
  q.tol_mm = narrow_tol_mm;
  if (ransac_plane(pts, n, q, out, soa, soa_cap) < 3) return 0;
  return refine_plane(pts, n, narrow_tol_mm, out);
}

}  // namespace pv::levelling
