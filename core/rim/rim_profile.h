// The rim's height from the stored points about a rim plane.
//
// The plane through the sector tops (rim_plane.h) takes each sector's
// third-highest point: an order statistic, which rises with the number of
// points near the top. A small pit without surround scanned 25 passes put
// its rim 0.17 mm higher than its single pass (+0.20 % against -0.004 %),
// and strays within 2 mm over a container's lip held sector tops and the
// plane 0.3 mm over the lip. Here the plane keeps its tilt and its height
// comes from the weighted heights of the points about it (each stored
// point weighs the points its bin's thinning level stands for), which do
// not move with how long the scan was:
// - a flat top (a container's lip: a peak of points many times the wall's
//   density) is at the mean height of the points above the wall's density;
// - a wall's top edge (no surround) is where a wall of the density below
//   it would end holding the weight above: the density in the band 2-5 mm
//   under the plane, and the weight from there up.
// Where neither reading is sure (too few points under the top, or a height
// more than kMaxShiftMm from the plane) the plane's own height stands.
#ifndef PV_RIM_RIM_PROFILE_H
#define PV_RIM_RIM_PROFILE_H

#include <cstdint>

namespace pv::rim {

struct RimProfile {
  static constexpr double kLoMm = -6.0;    // heights about the plane kept
  static constexpr double kHiMm = 3.0;
  static constexpr double kStepMm = 0.05;
  static constexpr int kBins = 180;         // (kHiMm - kLoMm) / kStepMm
  double weight[kBins] = {};
  uint32_t points[kBins] = {};
  // A point dz_mm above the plane standing for weight points.
  void add(double dz_mm, double weight_points);
};

// The rim's height above the plane the profile was taken about (0 where
// the profile cannot tell).
double rim_offset_mm(const RimProfile &p);

}  // namespace pv::rim

#endif
