#include "rim/rim_plane.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/angle.h"

namespace pv::rim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kNone = -1.0e30f;
constexpr uint32_t kMinSectors = 24;
// A plane through fewer sectors, kept apart (RimPlane::partial) for the
// caller to use only where no other opening is found: a deep pit scanned
// from one side shows the top of its near wall in half the sectors or less
// (seed 1 #085: the ground ring at one height in 19 of 36 sectors, the
// other sectors' tops 10-90 mm down the wall), refused NO_RIM.
constexpr uint32_t kMinPartialSectors = 18;
// Fewer still, down to this many, where no sector's top lies above the
// plane and kMinSectors sectors show a top on it or below it: the wall's
// highest edge, seen where it is seen and nowhere exceeded, the other
// sectors' tops lower down the wall. A 0.38 m3 bulge
// without surround scanned 15 deg off showed its rim in 16 sectors (0.19 mm
// RMS, level with its floor) and lower wall in the other 20: refused
// NO_RIM (tuning seed 5 #047).
constexpr uint32_t kMinTopPlaneSectors = 12;
// A plane through this many sectors may correct the start frame by up to
// kMaxSteepTiltDeg: a rounded bowl has no flat floor, and its floor-plane
// fit lay 33-49 deg off scans tilted 49-58 deg (seeds 1301 #107, #149 and
// 1302 #164, each refused NO_RIM with 28-33 sectors on one plane within
// 0.8 mm RMS).
constexpr uint32_t kSteepSectors = 28;
constexpr double kMaxSteepTiltDeg = 60.0;
constexpr double kOnPlaneMm = 2.0;
constexpr double kMaxRmsMm = 1.5;
// The most the rim plane may correct the floor-plane levelling: a bowl
// scanned from one side without ground was 12 deg off (pitvol-sim scan
// --family bowl --no-ground --arc 180 --seed 5: +10.2 % at the old 10 deg).
constexpr double kMaxTiltDeg = 20.0;

}  // namespace

void SectorTops::clear(double centre_x, double centre_y) {
  cx = centre_x;
  cy = centre_y;
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    for (int k = 0; k < kRimTops; ++k) z[s][k] = x[s][k] = y[s][k] = kNone, level[s][k] = 0;
    ceiling[s] = 1.0e30f;
  }
}

void SectorTops::offer(double px, double py, double pz, uint8_t bin_level) {
  const double a = angle_2pi(py - cy, px - cx);  // libm-free (common/angle.h)
  auto s = uint32_t(a * (kRimSectors / (2 * kPi)));
  if (s >= kRimSectors) s = kRimSectors - 1;
  const auto v = float(pz);
  if (!(v <= ceiling[s])) return;
  int k = kRimTops;
  while (k > 0 && v > z[s][k - 1]) --k;
  if (k == kRimTops) return;
  for (int q = kRimTops - 1; q > k; --q) {
    z[s][q] = z[s][q - 1];
    x[s][q] = x[s][q - 1];
    y[s][q] = y[s][q - 1];
    level[s][q] = level[s][q - 1];
  }
  level[s][k] = bin_level;
  z[s][k] = v;
  x[s][k] = float(px);
  y[s][k] = float(py);
}

namespace {

// A kept point whose bin is thinned this many levels less than the most
// thinned bin among the sector's kept points is not a top.
constexpr int kMaxLevelsBelow = 2;

// The sector's top: the highest point with two more within 3 mm below it,
// of the points whose bins are thinned about as much as the most thinned
// bin among those kept. A dense flat top (a vessel's lip, a ground ring)
// fills its layers and thins them, while the few points floating above it
// (multipath 2-40 mm in front of the surface, strays) keep the layers
// above at the lowest level: in a long scan each stands for 2^4 fewer
// points than a lip point, and three of them within 3 mm over the lip
// made the top. A bulge vessel scanned 28 passes had its rim plane fit
// 0.6 mm high and tilted by such tops (+2.7 % against its single pass's
// -0.08 %, fresh seed 1309 #282, looked at for this). A wall's top has its
// layers at one level (nothing dense beside it): as before.
int sector_top(const SectorTops &t, uint32_t s) {
  int top_level = 0;
  for (int k = 0; k < kRimTops && t.z[s][k] > kNone; ++k) top_level = std::max(top_level, int(t.level[s][k]));
  const auto dense = [&](int k) { return int(t.level[s][k]) + kMaxLevelsBelow >= top_level; };
  for (int k = 0; k + 2 < kRimTops; ++k) {
    if (t.z[s][k + 2] <= kNone) return -1;
    if (!dense(k)) continue;
    int below = 0;
    for (int j = k + 1; j < kRimTops && t.z[s][j] > kNone && t.z[s][k] - t.z[s][j] <= 3.0f; ++j) {
      below += dense(j) ? 1 : 0;
    }
    if (below >= 2) return k;
  }
  return -1;
}

}  // namespace

bool SectorTops::dig() {
  bool dug = false;
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    if (z[s][kRimTops - 1] <= kNone || sector_top(*this, s) >= 0) {
      ceiling[s] = kNone;  // kept as it is: nothing more is offered to it
      continue;
    }
    // The lowest kept point stays offered: if it is the first of a dense
    // top, its neighbours below it come with it.
    ceiling[s] = z[s][kRimTops - 1];
    for (int k = 0; k < kRimTops; ++k) z[s][k] = x[s][k] = y[s][k] = kNone;
    dug = true;
  }
  return dug;
}

RimPlane fit_rim_plane(const SectorTops &t) {
  RimPlane rp;
  bool use[kRimSectors];
  int top[kRimSectors];
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    top[s] = sector_top(t, s);
    use[s] = top[s] >= 0;
  }
  // The scanned tops, as doubles once: the consensus reads each 7140 times.
  double px[kRimSectors], py[kRimSectors], pz[kRimSectors];
  uint32_t nt = 0;
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    if (!use[s]) continue;
    px[nt] = double(t.x[s][top[s]]);
    py[nt] = double(t.y[s][top[s]]);
    pz[nt] = double(t.z[s][top[s]]);
    ++nt;
  }
  // Consensus first: every triple of sector tops (36 choose 3 = 7140) as a
  // plane; the one with most tops within kOnPlaneMm wins. A few sectors
  // whose top was not scanned (their highest points are lower wall) then
  // cannot tilt the start of the least squares. A triple's plane is its
  // normal m = (p_j - p_i) x (p_k - p_i); a top's height above it is
  // m . (p - p_i) / m_z, so the test needs no solve and no division. Only
  // which tops the winner keeps goes on: the least squares below refit the
  // plane from them.
  double m[3] = {0, 0, 1}, o[3] = {0, 0, 0};  // no triple: the plane z = 0
  uint32_t best = 0;
  for (uint32_t i = 0; i < nt; ++i) {
    for (uint32_t j = i + 1; j < nt; ++j) {
      const double ux = px[j] - px[i], uy = py[j] - py[i], uz = pz[j] - pz[i];
      for (uint32_t k = j + 1; k < nt; ++k) {
        const double vx = px[k] - px[i], vy = py[k] - py[i], vz = pz[k] - pz[i];
        const double mz = ux * vy - uy * vx;  // the determinant of the triple's solve
        if (std::fabs(mz) < 1e-6) continue;   // tops in a line: no plane
        const double mx = uy * vz - uz * vy, my = uz * vx - ux * vz;
        const double tol = kOnPlaneMm * std::fabs(mz);
        uint32_t cnt = 0;
        for (uint32_t q = 0; q < nt; ++q) {
          const double e = mx * (px[q] - px[i]) + my * (py[q] - py[i]) + mz * (pz[q] - pz[i]);
          cnt += std::fabs(e) <= tol;
        }
        if (cnt > best) {
          best = cnt;
          m[0] = mx, m[1] = my, m[2] = mz;
          o[0] = px[i], o[1] = py[i], o[2] = pz[i];
        }
      }
    }
  }
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    if (top[s] < 0) continue;
    const double e = m[0] * (double(t.x[s][top[s]]) - o[0]) + m[1] * (double(t.y[s][top[s]]) - o[1]) +
                     m[2] * (double(t.z[s][top[s]]) - o[2]);
    use[s] = std::fabs(e) <= kOnPlaneMm * std::fabs(m[2]);
  }
  double a = 0, b = 0, c = 0;  // z = a + b x + c y
  for (int round = 0; round < 3; ++round) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    uint32_t n = 0;
    for (uint32_t s = 0; s < kRimSectors; ++s) {
      if (!use[s]) continue;
      const int k = top[s];
      const Eigen::Vector3d q(1.0, double(t.x[s][k]), double(t.y[s][k]));
      A += q * q.transpose();
      r += q * double(t.z[s][k]);
      ++n;
    }
    if (n < kMinTopPlaneSectors) return rp;
    const Eigen::Vector3d sol = A.ldlt().solve(r);
    a = sol(0);
    b = sol(1);
    c = sol(2);
    double ss = 0;
    uint32_t kept = 0;
    for (uint32_t s = 0; s < kRimSectors; ++s) {
      const int k = top[s];
      if (k < 0) continue;
      const double e = double(t.z[s][k]) - (a + b * t.x[s][k] + c * t.y[s][k]);
      use[s] = std::fabs(e) <= kOnPlaneMm;
      if (use[s]) {
        ss += e * e;
        ++kept;
      }
    }
    rp.sectors = kept;
    rp.rms_mm = kept ? std::sqrt(ss / kept) : 0;
  }
  uint32_t above = 0, below = 0;  // sector tops over and under the plane
  for (uint32_t s = 0; s < kRimSectors; ++s) {
    const int k = top[s];
    if (k < 0) continue;
    const double e = double(t.z[s][k]) - (a + b * t.x[s][k] + c * t.y[s][k]);
    above += e > kOnPlaneMm;
    below += e < -kOnPlaneMm;
  }
  const bool top_plane = above == 0 && rp.sectors + below >= kMinSectors;
  const uint32_t min_sectors = top_plane ? kMinTopPlaneSectors : kMinPartialSectors;
  if (rp.sectors < min_sectors || rp.rms_mm > kMaxRmsMm) return rp;
  Eigen::Vector3d nrm(-b, -c, 1.0);
  nrm.normalize();
  const bool level = nrm.z() >= std::cos(kMaxTiltDeg * kPi / 180.0);
  if (rp.sectors < kMinSectors) {
    rp.partial = level;
  } else if (level) {
    rp.found = true;
  } else {
    rp.found = rp.sectors >= kSteepSectors && nrm.z() >= std::cos(kMaxSteepTiltDeg * kPi / 180.0);
    rp.steep = rp.found;
  }
  rp.normal = nrm;
  rp.d = nrm.z() * a;  // the plane passes through (0, 0, a)
  return rp;
}

}  // namespace pv::rim
