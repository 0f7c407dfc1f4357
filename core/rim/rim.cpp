#include "rim/rim.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "common/draws.h"

namespace pv::rim {

namespace {

constexpr double kMaxGroundTiltDeg = 20.0;

double median_of(double *v, size_t n) {
  std::nth_element(v, v + n / 2, v + n);
  return v[n / 2];
}

// The top band of the levelled heights: from z_top - band_ratio * z_top to
// z_hi = z_top + kAboveTopMm, z_top the 98 % quantile (Params::top_quantile). Points that float
// above the ground (multipath, dust; up to 40 mm, 0.3 % of a shallow pit's
// points in the sweeps) must not stretch it: at the 99.9 % quantile an
// 80 mm deep pit's band began 2 mm above its ground, the ground was not
// found and the rim came out 29 mm high (+40 %). A ground ring holds far
// more than 2 % of the points, so the quantile lies on it or below it.
constexpr double kAboveTopMm = 3.0;
struct Band {
  double z_from, z_hi;
};
Band top_band(const Eigen::Vector3d *pts, size_t n, const Params &p, double *scratch) {
  for (size_t i = 0; i < n; ++i) scratch[i] = pts[i].z();
  const size_t k = size_t(p.top_quantile * double(n - 1));
  std::nth_element(scratch, scratch + k, scratch + n);
  const double z_top = scratch[k];
  return Band{z_top - p.band_ratio * z_top, z_top + kAboveTopMm};
}

}  // namespace

Ground detect_ground(const Eigen::Vector3d *pts, size_t n, const Params &p,
                     double *scratch) {
  Ground g;
  if (n < 16) return g;
  const Band band = top_band(pts, n, p, scratch);

  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    if (pts[i].z() >= band.z_from && pts[i].z() <= band.z_hi) scratch[m++] = pts[i].z();
  }
  if (m < 16) return g;
  std::sort(scratch, scratch + m);
  // Densest window of peak_window_mm: two pointers over the sorted heights.
  size_t best_lo = 0, best_count = 0;
  for (size_t lo = 0, hi = 0; lo < m; ++lo) {
    while (hi < m && scratch[hi] - scratch[lo] <= p.peak_window_mm) ++hi;
    if (hi - lo > best_count) {
      best_count = hi - lo;
      best_lo = lo;
    }
  }
  if (double(best_count) < p.ground_share * double(m)) return g;
  g.found = true;
  g.points = uint32_t(best_count);
  g.z_mm = scratch[best_lo + best_count / 2];  // median of the peak
  return g;
}

GroundPlane fit_ground_plane(const Eigen::Vector3d *pts, size_t n, const Params &p,
                             double *scratch, uint32_t *idx) {
  GroundPlane gp;
  if (n < 64) return gp;
  const Band band = top_band(pts, n, p, scratch);
  const double z_from = band.z_from, z_hi = band.z_hi;
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    if (pts[i].z() >= z_from && pts[i].z() <= z_hi) idx[m++] = uint32_t(i);
  }
  if (m < 64) return gp;
  const double tol = 1.0;  // mm
  // How far from the levelling's vertical the ground may lie: the floor
  // plane of a bowl scanned from one side can be 12 deg off (pitvol-sim
  // scan --family bowl --arc 300 --seed 5: with a 10 deg limit the ground
  // is not found and the volume reads +22 %).
  const double cos_max = std::cos(kMaxGroundTiltDeg * 3.14159265358979323846 / 180.0);
  LcgDraws draws{0x9E3779B97F4A7C15ull};
  auto next = [&draws, m]() { return draws.next(m); };
  uint32_t best = 0;
  Eigen::Vector3d bn = Eigen::Vector3d::UnitZ();
  double bd = 0;
  for (int it = 0; it < 256; ++it) {
    const Eigen::Vector3d &a = pts[idx[next()]], &b = pts[idx[next()]], &c = pts[idx[next()]];
    Eigen::Vector3d nn = (b - a).cross(c - a);
    const double len = nn.norm();
    if (!(len > 1e-6)) continue;
    nn /= len;
    if (nn.z() < 0) nn = -nn;
    if (nn.z() < cos_max) continue;
    const double d = nn.dot(a);
    uint32_t cnt = 0;
    for (size_t q = 0; q < m; ++q) cnt += std::fabs(nn.dot(pts[idx[q]]) - d) <= tol;
    if (cnt > best) {
      best = cnt;
      bn = nn;
      bd = d;
    }
  }
  if (double(best) < p.ground_share * double(m) || best < 32) return gp;
  // Least squares on the inliers, twice.
  for (int round = 0; round < 2; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    uint32_t cnt = 0;
    for (size_t q = 0; q < m; ++q) {
      if (std::fabs(bn.dot(pts[idx[q]]) - bd) <= tol) {
        mean += pts[idx[q]];
        ++cnt;
      }
    }
    if (cnt < 32) return gp;
    mean /= double(cnt);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (size_t q = 0; q < m; ++q) {
      if (std::fabs(bn.dot(pts[idx[q]]) - bd) <= tol) {
        const Eigen::Vector3d v = pts[idx[q]] - mean;
        cov += v * v.transpose();
      }
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    Eigen::Vector3d nn = es.eigenvectors().col(0);
    if (nn.z() < 0) nn = -nn;
    bn = nn;
    bd = nn.dot(mean);
    gp.inliers = cnt;
  }
  if (bn.z() < cos_max) return gp;
  gp.found = true;
  gp.normal = bn;
  gp.d = bd;
  return gp;
}

// wall_top_mm(): weight above the top (within kFadeReachMm) worth more
// than kFadeMm of typical wall is a fading wall, not a top edge.
constexpr double kFadeMm = 10.0;
constexpr double kFadeReachMm = 100.0;

double wall_top_mm(const double *weight, const gridding::Grid &grid,
                   double *scratch) {
  const uint32_t first = grid.below + uint32_t(std::ceil(5.0 / grid.layer_mm));
  int64_t last = -1;
  for (uint32_t j = grid.layers; j-- > first;) {
    if (weight[j] > 0) {
      last = j;
      break;
    }
  }
  if (last < int64_t(first) + 8) return -1.0;
  size_t m = 0;
  for (uint32_t j = first; j <= uint32_t(last); ++j) scratch[m++] = weight[j];
  const double typical = median_of(scratch, m);
  if (!(typical > 0)) return -1.0;

  // Highest layer that, with the 3 below it, carries at least half the
  // typical wall weight: isolated strays above the rim do not qualify.
  int64_t top = -1;
  for (int64_t j = last; j >= int64_t(first) + 3; --j) {
    bool wall = true;
    for (int64_t q = j - 3; q <= j; ++q) wall = wall && weight[q] >= 0.5 * typical;
    if (wall) {
      top = j;
      break;
    }
  }
  if (top < 0) return -1.0;
  // A top edge ends the wall; a wall that fades out (its upper part seen
  // less and less, the rim never) leaves more above the half-weight layer
  // than kFadeMm of typical wall: no top was scanned (a 792 mm pit whose
  // scan thinned out from 560 mm read its top at 638 mm: -19 %).
  double above = 0;
  const int64_t reach = int64_t(std::ceil(kFadeReachMm / grid.layer_mm));
  for (int64_t q = top + 1; q <= std::min<int64_t>(last, top + reach); ++q) above += weight[q];
  if (above > typical * (kFadeMm / grid.layer_mm)) return -1.0;
  // Local weight of a full layer: mean of the 5 layers below the top.
  double local = 0;
  int64_t nloc = 0;
  for (int64_t q = top - 5; q < top; ++q) {
    if (q >= int64_t(first)) {
      local += weight[q];
      ++nloc;
    }
  }
  local = nloc > 0 ? local / double(nloc) : typical;
  // Occupied fraction of the top layer and of the one above it.
  double filled = std::min(1.0, weight[top] / local);
  if (uint32_t(top) + 1 < grid.layers) {
    filled += std::min(1.0, weight[top + 1] / local);
  }
  return grid.z_of(uint32_t(top)) - 0.5 * grid.layer_mm + filled * grid.layer_mm;
}

}  // namespace pv::rim
