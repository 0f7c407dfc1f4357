// The configurations of the session harnesses (fuzz_session.cpp), shared
// with the unit test that replays their findings (tests/unit/session/
// test_block_reuse.cpp), so that a regression input runs as it was found.
#ifndef PV_FUZZ_SESSION_CONFIG_H
#define PV_FUZZ_SESSION_CONFIG_H

#include <cstdint>
#include <cstring>
#include <vector>

#include "pitvol/pitvol.h"

namespace pv::fuzz {

// The harnesses' input: 8 bytes of seed, then three raw floats a point
// (a trailing partial point is ignored). size >= 8.
inline std::vector<pv_point_t> input_points(const uint8_t *data, size_t size, uint64_t *seed) {
  std::memcpy(seed, data, 8);
  std::vector<pv_point_t> pts((size - 8) / 12);
  if (!pts.empty()) std::memcpy(pts.data(), data + 8, pts.size() * 12);
  return pts;
}

// The surface model's grids, smaller than the default's (2 deg, 2 mm cells
// out to 320 mm: 5 MB written by every estimate and finish, most of an
// execution): the same code on fewer bins, or the coarse-bin code of the
// MCU profile (pv_config_mcu()). fuzz_session's paper and polar
// use the fine grids for the model their plausibility checks build.
enum class Grids { Default, Fine, Coarse };

// A small configuration (64 layers of 2 mm, 64 points per layer, 16 RANSAC
// draws) keeps an execution short and its bins thinning.
inline void session_config(pv_config_t *cfg, pv_method_t m, Grids grids) {
  pv_config_default(cfg);
  cfg->method = m;
  if (grids == Grids::Fine) {
    cfg->surface_theta_bins = 90;
    cfg->surface_cell_mm = 4.0f;
    cfg->surface_max_radius_mm = 160.0f;
    cfg->surface_floor_points = 4096;
  } else if (grids == Grids::Coarse) {
    cfg->surface_theta_bins = 36;
    cfg->surface_wall_dz_mm = 12.0f;
    cfg->surface_cell_mm = 12.0f;
    cfg->surface_max_radius_mm = 240.0f;
    cfg->surface_floor_points = 2560;
    cfg->surface_band_mm = 3.0f;
    cfg->surface_coarse_bins = 1;
  }
  cfg->max_layers = 64;
  cfg->layer_mm = 2.0f;
  cfg->points_per_layer = 64;
  cfg->level_sample_points = 256;
  cfg->warmup_points = 256;
  // The fewest RANSAC draws the validation allows: the plane fit's
  // comparisons under coverage instrumentation were 65 % of an execution
  // at the default 256.
  cfg->ransac_iterations = 16;
}

}  // namespace pv::fuzz

#endif
