// The rim as a plane, for scans without a ground ring (method surface).
//
// Levelling on the floor plane (the paper's rule) leaves the scan tilted
// where the floor is not flat: a bowl's lowest part, an uneven hand-dug
// floor. Without ground around the pit, the top edge of the wall is what
// defines the lid. Per angular sector around the pit's centre, the top of
// the wall is the highest point with two more within 3 mm below it (far
// strays float alone above the rim), of the points whose layer bins are
// thinned within two levels of the most thinned among those kept (over a
// dense flat top, multipath keeps the layers above it less thinned); a
// plane through the sector tops, with outliers dropped, is the rim.
#ifndef PV_RIM_RIM_PLANE_H
#define PV_RIM_RIM_PLANE_H

#include <Eigen/Core>
#include <cstdint>

namespace pv::rim {

constexpr uint32_t kRimSectors = 36;
constexpr int kRimTops = 8;

// A sector keeps its kRimTops highest points. Where far strays fill them
// all (a long or large scan: 8 strays above the rim of one 10 deg sector),
// dig() lowers that sector's ceiling to its lowest kept point and empties
// it, and the points are offered again: the strays are dug through, not
// counted, and the memory stays 36 x 8 points.
struct SectorTops {
  double cx = 0, cy = 0;             // centre of the sectors
  float z[kRimSectors][kRimTops];    // highest first
  float x[kRimSectors][kRimTops], y[kRimSectors][kRimTops];
  uint8_t level[kRimSectors][kRimTops];  // the thinning level of each point's bin
  float ceiling[kRimSectors];        // points above it are not offered
                                     // (kNone: a sector dig() left closed)
  void clear(double centre_x, double centre_y);
  void offer(double px, double py, double pz, uint8_t bin_level = 0);
  // Full sectors without a top: ceiling lowered, emptied. Returns whether
  // any was (offer the points again then).
  bool dig();
};
// Rounds of SectorTops::dig() (passes over the points) at most.
constexpr int kRimDigRounds = 6;

struct RimPlane {
  bool found = false;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // upward
  double d = 0;                       // plane: normal . p = d
  uint32_t sectors = 0;               // sectors on the plane
  double rms_mm = 0;
  bool steep = false;    // found beyond 20 deg of the start frame
  bool partial = false;  // not found: 18-23 sectors on a plane within 20 deg
                         // (12-23 where no top lies above it)
};

// A plane through the sector tops: found with at least 24 sectors on it
// (residual under 2 mm), an RMS under 1.5 mm and within 20 deg of level,
// or with at least 28 sectors within 60 deg (steep); partial with 18-23
// sectors within 20 deg, or 12-23 with no sector's top above the plane and
// 24 or more on it or below it (normal and d filled for the caller's last
// resort).
RimPlane fit_rim_plane(const SectorTops &tops);

}  // namespace pv::rim

#endif
