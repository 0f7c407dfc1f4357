#include "area/polar_area.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "common/angle.h"

namespace pv::area {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxCoef = 2 * int(kMaxHarmonics) + 1;
using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCoef, kMaxCoef>;
using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCoef, 1>;

double median_of(double *v, size_t n) {
  std::nth_element(v, v + n / 2, v + n);
  return v[n / 2];
}

// Basis values 1, cos t, sin t, ..., cos Kt, sin Kt by the recurrence;
// t in [0, 2 pi) (pv::angle_2pi).
void basis(double t, uint32_t K, double *phi) {
  double s1, c1;
  sin_cos(t, &s1, &c1);
  phi[0] = 1.0;
  double c = 1.0, s = 0.0;
  for (uint32_t k = 1; k <= K; ++k) {
    const double cn = c * c1 - s * s1, sn = s * c1 + c * s1;
    c = cn;
    s = sn;
    phi[2 * k - 1] = c;
    phi[2 * k] = s;
  }
}

// Least squares over the points with keep[i]; false if singular.
bool fit(const double *theta, const double *r, const uint8_t *keep, size_t n, uint32_t K, Vec *a) {
  const int m = int(2 * K + 1);
  Mat M = Mat::Zero(m, m);
  Vec b = Vec::Zero(m);
  double phi[kMaxCoef];
  for (size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    basis(theta[i], K, phi);
    for (int u = 0; u < m; ++u) {
      b[u] += phi[u] * r[i];
      for (int v = u; v < m; ++v) M(u, v) += phi[u] * phi[v];
    }
  }
  M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
  const Eigen::LDLT<Mat> ldlt(M);
  if (ldlt.info() != Eigen::Success) return false;
  const Vec d = ldlt.vectorD();
  if (!(d.minCoeff() > 1e-10 * d.cwiseAbs().maxCoeff())) return false;
  *a = ldlt.solve(b);
  return true;
}

double eval(const Vec &a, uint32_t K, double t) {
  double phi[kMaxCoef];
  basis(t, K, phi);
  double v = 0;
  for (int u = 0; u < int(2 * K + 1); ++u) v += a[u] * phi[u];
  return v;
}

}  // namespace

size_t polar_scratch_needed(size_t n) { return 4 * n; }

bool polar_area(const XY *pts, size_t n, const PolarParams &p, double *scratch, size_t scratch_cap,
                PolarResult *out) {
  if (pts == nullptr || out == nullptr || n < 16 || scratch_cap < polar_scratch_needed(n)) return false;
  double *theta = scratch, *r = scratch + n, *work = scratch + 2 * n;
  auto *keep = reinterpret_cast<uint8_t *>(scratch + 3 * n);  // n bytes of the last n doubles

  // Centre: coordinate-wise median.
  for (size_t i = 0; i < n; ++i) work[i] = pts[i].x_mm;
  const double cx = median_of(work, n);
  for (size_t i = 0; i < n; ++i) work[i] = pts[i].y_mm;
  const double cy = median_of(work, n);
  for (size_t i = 0; i < n; ++i) {
    // No libm (common/angle.h): the same bits on every target.
    const double dx = pts[i].x_mm - cx, dy = pts[i].y_mm - cy;
    theta[i] = angle_2pi(dy, dx);
    r[i] = std::sqrt(dx * dx + dy * dy);
    keep[i] = 1;
  }
  // Largest angular gap: sort a copy of the angles.
  for (size_t i = 0; i < n; ++i) work[i] = theta[i];
  std::sort(work, work + n);
  double gap = work[0] + 2 * kPi - work[n - 1];
  for (size_t i = 1; i < n; ++i) gap = std::max(gap, work[i] - work[i - 1]);
  out->max_gap_deg = gap * 180.0 / kPi;
  if (out->max_gap_deg > p.max_gap_deg) return false;

  uint32_t K = std::min<uint32_t>({p.max_harmonics, kMaxHarmonics,
                                   uint32_t(n / (2 * std::max<uint32_t>(1, p.points_per_coefficient)))});
  K = std::min<uint32_t>(K, uint32_t(std::floor(kPi / std::max(gap, 1e-6))));
  Vec a;
  if (!fit(theta, r, keep, n, K, &a)) return false;
  // Trim: residual band from the MAD of the residuals, then refit.
  for (size_t i = 0; i < n; ++i) work[i] = std::fabs(r[i] - eval(a, K, theta[i]));
  const double mad = median_of(work, n);
  // 3 sigma, with sigma = 1.4826 MAD (normal consistency).
  const double band = std::max(p.min_band_mm, 3.0 * 1.4826 * mad);
  size_t used = 0;
  for (size_t i = 0; i < n; ++i) {
    keep[i] = std::fabs(r[i] - eval(a, K, theta[i])) <= band;
    used += keep[i];
  }
  if (used < 16 || !fit(theta, r, keep, n, K, &a)) return false;
  double s = a[0] * a[0];
  for (uint32_t k = 1; k <= K; ++k) s += 0.5 * (a[2 * k - 1] * a[2 * k - 1] + a[2 * k] * a[2 * k]);
  out->area_mm2 = kPi * s;
  out->harmonics = K;
  out->points_used = uint32_t(used);
  return std::isfinite(out->area_mm2);
}

}  // namespace pv::area
