#include "rim/support_plane.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>  // cross

#include "common/angle.h"
#include "common/draws.h"
#include "levelling/plane_fit.h"

namespace pv::rim {

namespace {

constexpr double kOnMm = 1.0;          // on the plane: as fit_ground_plane()
constexpr double kAboveMm = 3.0;       // above it: beyond noise and grooves' lips
constexpr double kAboveShare = 0.015;  // strays of a long scan stay under it
constexpr double kAboveWeight = 2.0;   // score: points on less twice those above
constexpr double kMinOnShare = 0.004;  // a deep pit's sparse ground: 0.7 %
constexpr uint32_t kMinOn = 32;
constexpr double kTopShare = 0.03;     // candidates: the highest 3 % of points,
constexpr uint32_t kMinTop = 64;
constexpr uint32_t kSectors = 36;      // and the 4 highest of each 10 deg
constexpr uint32_t kPerSector = 4;     // sector around the scan's centre
constexpr int kDraws = 512;
static_assert(kSectors * kPerSector == kSupportIndexExtra, "index scratch: n + the sector tops");

struct Count {
  uint32_t on = 0, above = 0;
};

Count count(const Eigen::Vector3d *pts, size_t n, const Eigen::Vector3d &nn, double d) {
  Count c;
  for (size_t i = 0; i < n; ++i) {
    const double h = nn.dot(pts[i]) - d;
    c.on += std::fabs(h) <= kOnMm;
    c.above += h > kAboveMm;
  }
  return c;
}

// An opening: enough points on it, few above it (strays), fewer than on it.
bool is_opening(const Count &c, size_t n) {
  return c.on >= kMinOn && c.above <= uint32_t(kAboveShare * double(n)) && c.above <= c.on;
}

// The kPerSector highest points of each sector around (cx, cy), appended
// to idx. In a frame far from level the highest points overall lie on one
// side, where a sparse ground gives too few of them for three to be drawn
// together; per sector, the ground's points lead all round.
size_t sector_tops(const Eigen::Vector3d *pts, size_t n, uint32_t *idx) {
  double cx = 0, cy = 0;
  for (size_t i = 0; i < n; ++i) {
    cx += pts[i].x();
    cy += pts[i].y();
  }
  cx /= double(n);
  cy /= double(n);
  uint32_t top[kSectors][kPerSector];
  uint32_t filled[kSectors] = {};
  for (size_t i = 0; i < n; ++i) {
    uint32_t s = uint32_t(angle_2pi(pts[i].y() - cy, pts[i].x() - cx) * (kSectors / kTwoPi));
    if (s >= kSectors) s = kSectors - 1;
    uint32_t *t = top[s];
    uint32_t j = filled[s];
    if (j == kPerSector) {
      if (!(pts[i].z() > pts[t[kPerSector - 1]].z())) continue;
      j = kPerSector - 1;
    } else {
      ++filled[s];
    }
    for (; j > 0 && pts[t[j - 1]].z() < pts[i].z(); --j) t[j] = t[j - 1];
    t[j] = uint32_t(i);
  }
  size_t m = 0;
  for (uint32_t s = 0; s < kSectors; ++s) {
    for (uint32_t j = 0; j < filled[s]; ++j) idx[m++] = top[s][j];
  }
  return m;
}

}  // namespace

SupportPlane fit_support_plane(const Eigen::Vector3d *pts, size_t n, double max_tilt_deg,
                               double *z, uint32_t *idx) {
  SupportPlane sp;
  if (n < 2 * kMinTop) return sp;
  size_t m = sector_tops(pts, n, idx);
  // The highest points overall: where the ground is dense, most of them.
  const size_t k = std::max<size_t>(kMinTop, size_t(kTopShare * double(n)));
  for (size_t i = 0; i < n; ++i) z[i] = pts[i].z();
  std::nth_element(z, z + (n - k), z + n);
  const double z_cut = z[n - k];
  for (size_t i = 0, added = 0; i < n && added < k; ++i) {
    if (pts[i].z() >= z_cut) {
      idx[m++] = uint32_t(i);
      ++added;
    }
  }
  // Tilts compared as angles: libm's cos would not give the same bits on
  // every target (common/angle.h).
  const double max_tilt = max_tilt_deg * 3.14159265358979323846 / 180.0;
  const auto too_tilted = [max_tilt](const Eigen::Vector3d &nn) {
    return angle_of_cos(nn.z()) > max_tilt;
  };
  // Deterministic draws: the same scan gives the same plane.
  LcgDraws draws{0xD1B54A32D192ED03ull};
  auto next = [&draws, m]() { return draws.next(m); };
  // Of the openings drawn, the one with most points on it less twice those
  // above: of two planes through the same sparse strip of ground, the one
  // that leaves fewer points above.
  bool any = false;
  double best = 0;
  Eigen::Vector3d bn = Eigen::Vector3d::UnitZ();
  double bd = 0;
  for (int it = 0; it < kDraws; ++it) {
    const Eigen::Vector3d &a = pts[idx[next()]], &b = pts[idx[next()]], &c = pts[idx[next()]];
    Eigen::Vector3d nn = (b - a).cross(c - a);
    const double len = nn.norm();
    if (!(len > 1e-6)) continue;
    nn /= len;
    if (nn.z() < 0) nn = -nn;
    if (too_tilted(nn)) continue;
    const double d = nn.dot(a);
    const Count ct = count(pts, n, nn, d);
    if (!is_opening(ct, n)) continue;
    const double score = double(ct.on) - kAboveWeight * double(ct.above);
    if (!any || score > best) {
      any = true;
      best = score;
      bn = nn;
      bd = d;
    }
  }
  if (!any) return sp;
  // Total least squares on the points on the plane, three rounds (the
  // levelling's refinement: n . p + d = 0, so d is minus this plane's).
  levelling::Plane plane{bn, -bd};
  for (int round = 0; round < 3; ++round) {
    if (levelling::refine_plane(pts, n, kOnMm, &plane) < kMinOn) return sp;
  }
  if (plane.n.z() < 0) plane = levelling::Plane{-plane.n, -plane.d};
  bn = plane.n;
  bd = -plane.d;
  const Count ct = count(pts, n, bn, bd);
  sp.on = ct.on;
  sp.above = ct.above;
  if (too_tilted(bn) || !is_opening(ct, n) || double(ct.on) < kMinOnShare * double(n)) return sp;
  sp.found = true;
  sp.normal = bn;
  sp.d = bd;
  return sp;
}

}  // namespace pv::rim
