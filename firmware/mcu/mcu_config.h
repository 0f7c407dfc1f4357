// The MCU configuration: capacities small enough that the session block
// fits in 512 KB (docs/memory.md has the size table, docs/targets.md its
// accuracy against the default configuration). Only capacities and the
// layer height change (and the method, see below); every method parameter
// keeps its default.
#ifndef PV_FIRMWARE_MCU_CONFIG_H
#define PV_FIRMWARE_MCU_CONFIG_H

#include "pitvol/pitvol.h"

// The block budget of the MCU build; the linker script reserves exactly
// this much for the block (firmware/mcu/mps2_an500.ld).
#define PV_MCU_BLOCK_BYTES (512u * 1024u)

static inline void pv_mcu_config(pv_config_t *cfg) {
  pv_config_default(cfg);
  // The default method's surface model (an 11.8 MB workspace at finish, and
  // the 786 KB floor store) does not fit yet: the MCU runs the paper's
  // method until a compact surface summary exists (docs/targets.md).
  cfg->method = PV_METHOD_PAPER;
  // The duplicate filter's fixed 1 MiB does not fit either (docs/targets.md).
  cfg->duplicate_filter = 0;
  cfg->layer_mm = 2.0f;            // the thickest layer allowed (default 0.5)
  cfg->max_layers = 176;           // 352 mm of depth range
  cfg->points_per_layer = 128;     // default 1024
  cfg->level_sample_points = 512;  // default 8192
  cfg->warmup_points = 2048;       // default 32768
}

#endif
