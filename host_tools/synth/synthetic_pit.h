// A deterministic synthetic scan of a pit whose volume is known exactly.
//
// A stand-in for the full scanner simulator (ray casting, occlusion): it
// samples the surfaces of a frustum-shaped pit (a cylinder when the two
// radii are equal) directly, with uneven density like a handheld scan
// (dense floor, sparser upper wall), range noise, floating multipath points
// inside the void, a few far strays, optional ground around the rim, and a
// rigid transform (tilt, yaw, offset, optionally upside down). Points are
// generated one at a time, so a 10-million-point stream needs no storage.
#ifndef PV_SYNTH_SYNTHETIC_PIT_H
#define PV_SYNTH_SYNTHETIC_PIT_H

#include <cstdint>

#include "pitvol/pitvol.h"

namespace pv::synth {

struct PitSpec {
  double radius_bottom_mm = 110.0;
  double radius_top_mm = 110.0;
  double depth_mm = 290.0;
  double ground_width_mm = 60.0;  // 0: no ground around the rim
  double noise_mm = 0.05;         // Gaussian range noise (sigma)
  double floor_share = 0.25;      // share of surface points on the floor
  double ground_share = 0.15;     // share on the ground ring (if any)
  double multipath_share = 0.01;  // points floating inside the void
  double stray_share = 0.0005;    // far strays around the pit
  double tilt_deg = 12.0;
  double tilt_azimuth_deg = 30.0;
  double yaw_deg = 40.0;
  double offset_mm[3] = {350.0, -120.0, 900.0};
  bool upside_down = false;
  uint64_t seed = 1;
};

// Void volume below the rim plane, closed form (frustum), in cm^3.
double exact_volume_cm3(const PitSpec &s);

// Streams n points of the scan to path as binary little-endian float PLY,
// with the spec and the exact volume in header comments. No point array,
// so any n fits in memory. Returns false if the file cannot be written.
bool write_scan_ply(const char *path, const PitSpec &s, uint64_t n);

class PitScan {
 public:
  explicit PitScan(const PitSpec &s);
  pv_point_t next();
  // The true (noise-free) levelled position of the last point's surface is
  // not exposed: tests compare volumes, never points.

 private:
  double uniform();
  double gaussian();
  void surface_point(double *p);
  PitSpec s_;
  uint64_t state_;
  double R_[9];
};

}  // namespace pv::synth

#endif
