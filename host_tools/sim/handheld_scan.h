// A simulated handheld structured-light scan of a Pit.
//
// A scanner pose moves on a path above and around the pit, looking in; each
// frame casts a grid of rays over the field of view (Embree 3), keeps the
// first hit (occlusion), adds range noise along the ray, replaces a share of
// hits by multipath points floating in the void in front of the wall, and
// adds a few far strays. Density comes out uneven the way real scans are:
// dense floor from overlapping views, sparse steep upper walls, shadows
// under overhangs. Finally one random rigid transform (tilt, yaw, offset)
// puts the cloud in the scanner's world frame, so it is not level.
// Deterministic in (pit, params).
#ifndef PV_SIM_HANDHELD_SCAN_H
#define PV_SIM_HANDHELD_SCAN_H

#include <cstdint>
#include <memory>
#include <vector>

#include "pitvol/pitvol.h"
#include "sim/pit_geometry.h"

namespace pv::sim {

struct ScanParams {
  uint64_t seed = 1;
  uint32_t target_points = 300000;  // stop after the frame that reaches it
  double noise_mm = 0.05;           // sigma along the ray (0.02 .. 0.2)
  double multipath_share = 0.01;    // hits replaced by floating points
  double stray_share = 0.0005;      // far strays
  double max_tilt_deg = 25.0;       // random tilt in [0, max]; any yaw
  double fov_deg = 50.0;
  uint32_t rays_x = 80, rays_y = 60;  // ray grid per frame
  double frames_per_s = 20.0;       // timestamps of the frame stream
  // Stress options (the defaults leave every scan bit-identical):
  // - path_arc_deg < 360: the operator walks only part of the way round;
  //   the scanner's azimuth sweeps back and forth over this arc instead of
  //   circling, stays at the rim (1.0-1.25 x the pit radius out, not over
  //   the pit) and aims mostly across at the far wall, so the wall below the
  //   walked arc is seen little or not at all (one side missing; at 90 deg
  //   about a 60 deg sector of wall gets nearly nothing);
  // - dropout_patches > 0: wet or dark soil that returns nothing: that many
  //   balls, radius drawn in [dropout_radius_min_mm, max], centred on points
  //   drawn uniformly (by area) on the wall and floor; a hit inside a ball
  //   emits nothing (no point, no multipath, no stray).
  double path_arc_deg = 360.0;
  uint32_t dropout_patches = 0;
  double dropout_radius_min_mm = 20.0;
  double dropout_radius_max_mm = 40.0;
  // Envelope options (sim/envelope.h), defaults as above:
  // - transform_seed != 0: the rigid transform into the world frame is
  //   drawn from this seed instead of `seed`, so that passes with their own
  //   seeds (paths, noise) share one pose of the pit;
  // - the tilt is drawn in [min_tilt_deg, max_tilt_deg];
  // - outside_views > 0: for about that share of the path the operator
  //   steps back (1.15-1.55 x the pit radius out, 20-100 mm above the rim)
  //   and aims at the wall just below the rim from outside: a container's
  //   outer wall, seen as a handheld scan of one sees part of it.
  uint64_t transform_seed = 0;
  double min_tilt_deg = 0.0;
  double outside_views = 0.0;
};

// How much of the wall a scan saw: the wall (triangles steeper than 45 deg,
// not the ground ring or lip) in 36 sectors x 16 height bands between the
// lowest vertex and the rim; a cell is seen once 3 returns came from it.
// And the rim, in the same 36 sectors: the wall's top kRimBandMm and the
// ground or lip within kRimBandMm outside the pit's widest radius. A
// sector is seen once 3 returns came from it.
constexpr int kCoverageSectors = 36, kCoverageBands = 16;
constexpr double kRimBandMm = 10.0;
struct WallCoverage {
  double unseen_share = 0.0;  // wall area in cells never seen / wall area
  uint32_t cells = 0, unseen_cells = 0;
  uint32_t rim_sectors = 0, rim_unseen_sectors = 0;
};

// A dropout patch, in the pit frame.
struct DropoutPatch {
  double x_mm, y_mm, z_mm, radius_mm;
};

struct Frame {
  uint32_t sequence;
  uint64_t timestamp_us;
  std::vector<pv_point_t> points;  // world frame, millimetres
};

WallCoverage wall_coverage_of(const std::vector<double> &area, const std::vector<uint32_t> &hits);

class HandheldScan {
 public:
  HandheldScan(const Pit &pit, const ScanParams &p);
  ~HandheldScan();
  HandheldScan(const HandheldScan &) = delete;
  HandheldScan &operator=(const HandheldScan &) = delete;
  // Next frame; false when the scan is complete (target reached or the path
  // ended). Frames may hold 0 points.
  bool next(Frame *out);
  // The applied rigid transform, world = R * pit + t (row-major R).
  void transform(double R[9], double t[3]) const;
  double tilt_deg() const;
  // The dropout patches drawn for this scan (empty by default).
  const std::vector<DropoutPatch> &dropout_patches() const;
  // The wall seen by the frames returned so far, and its cells (area,
  // returns; the wall's cells, then the rim's sectors) for summing several
  // passes (wall_coverage_of).
  WallCoverage wall_coverage() const;
  void wall_cells(std::vector<double> *area, std::vector<uint32_t> *hits) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pv::sim

#endif
