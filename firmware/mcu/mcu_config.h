// The MCU configuration: capacities small enough that the session block
// fits in 512 KB (docs/memory.md has the size table, docs/targets.md its
// accuracy against the default configuration). Only capacities, grid sizes
// and the layer height change; every other method parameter keeps its
// default.
#ifndef PV_FIRMWARE_MCU_CONFIG_H
#define PV_FIRMWARE_MCU_CONFIG_H

#include "pitvol/pitvol.h"

// The block budget of the MCU build; the linker script reserves exactly
// this much for the block (firmware/mcu/mps2_an500.ld).
#define PV_MCU_BLOCK_BYTES (512u * 1024u)

static inline void pv_mcu_config(pv_config_t *cfg) {
  pv_config_default(cfg);
  // The default method, surface, with coarser grids and fewer stored points
  // (measured against the default configuration: docs/targets.md).
  cfg->method = PV_METHOD_SURFACE;
  // The duplicate filter's fixed 1 MiB does not fit (docs/targets.md).
  cfg->duplicate_filter = 0;
  cfg->layer_mm = 2.0f;             // the thickest layer allowed (default 0.5)
  cfg->max_layers = 200;            // 400 mm of depth range (+40 mm below)
  cfg->points_per_layer = 64;       // the least allowed (default 1024)
  cfg->level_sample_points = 2048;  // default 8192; 1024 mislevelled a bowl (+20 %)
  cfg->warmup_points = 256;         // default 32768
  cfg->surface_floor_points = 2560; // default 65536
  cfg->surface_theta_bins = 36;     // 10 deg (default 180: 2 deg)
  cfg->surface_wall_dz_mm = 12.0f;  // default 2
  cfg->surface_cell_mm = 12.0f;     // default 2
  cfg->surface_max_radius_mm = 240.0f;  // default 320; the widest corpus pit is 205
  // A bin of 10 deg spans more radius on an oval wall than one of 2 deg: with
  // the default 1.5 mm band its few points read near its largest radius
  // (ellipses +2.5 %); 3 mm halved that (docs/targets.md, the sweep).
  cfg->surface_band_mm = 3.0f;
  // Its 10 deg x 12 mm bins hold a few points each: borrowed slopes, the
  // floor flood at the default's slope and the interval's term for them
  // (docs/targets.md).
  cfg->surface_coarse_bins = 1;
}

#endif
