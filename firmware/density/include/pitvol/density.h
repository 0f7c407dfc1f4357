/*
 * In-place density of the excavated soil from the pit's volume
 * (docs/density.md):
 *
 *   wet density          rho_wet = m / V
 *   dry density          rho_dry = rho_wet / (1 + w)      w = moisture / 100
 *   relative compaction  RC      = rho_dry / rho_dry,max * 100 %
 *
 * m: wet mass of the soil taken out of the pit (g), V: the pit's volume
 * (cm3), w: water content as a share of the dry mass (field practice gives
 * it in %), rho_dry,max: the reference maximum dry density of the material
 * (Proctor test, kg/m3) from the configuration.
 *
 * Uncertainty: the volume lies in V +/- dV (pv_result_t.interval_cm3).
 * Every quantity falls as V grows, so its range is the exact image of the
 * volume interval: low at V + dV, high at V - dV (asymmetric, no
 * linearisation). Mass and moisture are taken as exact; their own error
 * adds to this range. If dV >= V there is no upper bound: the flag
 * PV_DENSITY_UNBOUNDED is set and the high values are 0.
 *
 * Densities in kg/m3 (1 g/cm3 = 1000 kg/m3 = 1 Mg/m3).
 */
#ifndef PITVOL_DENSITY_H
#define PITVOL_DENSITY_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Flag bits, equal to pitvol.DensityFlag of the serial protocol. */
#define PV_DENSITY_WET        (1u << 0) /* wet_* valid (a mass was given) */
#define PV_DENSITY_DRY        (1u << 1) /* dry_* valid (a moisture too) */
#define PV_DENSITY_COMPACTION (1u << 2) /* compaction_* valid (a reference too) */
#define PV_DENSITY_UNBOUNDED  (1u << 3) /* interval >= volume: no upper bounds */

/* Accepted ranges of the inputs. */
#define PV_DENSITY_MAX_MOISTURE_PERCENT 500.0
#define PV_DENSITY_MIN_REFERENCE_KG_M3 500.0
#define PV_DENSITY_MAX_REFERENCE_KG_M3 3500.0

typedef struct pv_density_input {
  double volume_cm3;        /* > 0, the measured pit volume */
  double interval_cm3;      /* >= 0, the volume's +/- interval */
  int has_mass;
  double mass_g;            /* > 0: wet mass of the excavated soil */
  int has_moisture;
  double moisture_percent;  /* 0 .. 500: water content, % of dry mass */
  double reference_max_dry_kg_m3; /* 0: none; else 500 .. 3500 */
} pv_density_input_t;

typedef struct pv_density {
  uint32_t flags;           /* PV_DENSITY_* */
  double wet_kg_m3, wet_low_kg_m3, wet_high_kg_m3;
  double dry_kg_m3, dry_low_kg_m3, dry_high_kg_m3;
  double compaction_percent, compaction_low_percent, compaction_high_percent;
} pv_density_t;

typedef enum pv_density_status {
  PV_DENSITY_OK = 0,
  PV_DENSITY_ERR_INVALID_ARGUMENT = 1, /* NULL pointer */
  PV_DENSITY_ERR_VOLUME = 2,    /* volume not > 0 or interval < 0 (or not finite) */
  PV_DENSITY_ERR_MASS = 3,      /* mass not > 0 */
  PV_DENSITY_ERR_MOISTURE = 4,  /* moisture outside 0 .. 500 % */
  PV_DENSITY_ERR_REFERENCE = 5  /* reference max dry density outside 500 .. 3500 kg/m3 */
} pv_density_status_t;

const char *pv_density_status_name(pv_density_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_density_status_message(pv_density_status_t status);

/* Without a mass: PV_DENSITY_OK with flags 0 (nothing to compute). On an
 * error *out is all zero. */
pv_density_status_t pv_density_compute(const pv_density_input_t *in, pv_density_t *out);

/* Unit helpers for screens and reports. */
double pv_density_kg_m3_to_g_cm3(double kg_m3);
double pv_density_kg_m3_to_lb_ft3(double kg_m3);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_DENSITY_H */
