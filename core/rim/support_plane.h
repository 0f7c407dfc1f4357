// The opening as a support plane (method surface), when neither the ground
// ring nor the rim plane was found in the levelling's frame.
//
// Whatever surrounds a pit (ground, a container's lip, nothing but the wall's
// top edge), the opening lies on the plane that has the whole scan below it
// and a dense set of points on it. fit_ground_plane() and fit_rim_plane()
// look for it in a frame levelled on the floor; two cases defeat them, both
// measured on the tuning sweeps (seeds 1 and 1300):
// - a ground ring that holds under a quarter of the top band (a deep pit
//   whose sparse ground is 0.7 % of the points: 256 RANSAC draws over the
//   band never pick three of its points), refused PV_ERR_NO_RIM;
// - a floor-plane frame far from level: a rounded bowl has no flat floor,
//   and the floor fit settles on a tangent plane 20-40 deg off, beyond the
//   20 deg the fits allow; the volume then came out +57 % and +74 % with
//   PV_OK.
// Here the candidates are the highest points of the scan and of each
// sector around it (a support plane is made of them). A plane is an opening
// if at least kMinOn points lie on it (within kOnMm) and at most kAboveShare
// of the points (strays), and no more than lie on it, float more than
// kAboveMm above it; of the openings drawn, the one with most points on it
// less twice those above wins.
#ifndef PV_RIM_SUPPORT_PLANE_H
#define PV_RIM_SUPPORT_PLANE_H

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

namespace pv::rim {

struct SupportPlane {
  bool found = false;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // upward
  double d = 0;                                        // plane: normal . p = d
  uint32_t on = 0;                                     // points within kOnMm
  uint32_t above = 0;                                  // points above kAboveMm
};

// pts: the levelled sample (any frame within max_tilt_deg of level).
// z_scratch: n entries; index_scratch: n + kSupportIndexExtra entries.
constexpr size_t kSupportIndexExtra = 144;
SupportPlane fit_support_plane(const Eigen::Vector3d *pts, size_t n, double max_tilt_deg,
                               double *z_scratch, uint32_t *index_scratch);

}  // namespace pv::rim

#endif
