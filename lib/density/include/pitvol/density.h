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

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Flag bits, equal to pitvol.DensityFlag of the serial protocol. */
#define PV_DENSITY_WET        (1u << 0) /* wet_* valid (a mass was given) */
#define PV_DENSITY_DRY        (1u << 1) /* dry_* valid (a moisture too) */
#define PV_DENSITY_COMPACTION (1u << 2) /* compaction_* valid (a reference too) */
#define PV_DENSITY_UNBOUNDED  (1u << 3) /* interval >= volume: no upper bounds */

/* Plausible ranges of the inputs (docs/density.md): a value outside is a
 * typing or unit mistake, refused rather than carried into the log. A
 * test pit holds a few hundred grams to a few tens of kilograms of soil;
 * field soils hold 0 to 100 % water (of their dry mass); Proctor maximum
 * dry densities lie between about 1.1 and 2.5 g/cm3; specifications ask
 * for 85 to 100 % compaction. pitvol-report checks the same numbers
 * (tests/report reads them from here). */
#define PV_DENSITY_MIN_MASS_G 50.0
#define PV_DENSITY_MAX_MASS_G 100000.0
#define PV_DENSITY_MAX_MOISTURE_PERCENT 100.0
#define PV_DENSITY_MIN_REFERENCE_KG_M3 1000.0
#define PV_DENSITY_MAX_REFERENCE_KG_M3 2800.0
#define PV_DENSITY_MIN_REQUIRED_PERCENT 50.0
#define PV_DENSITY_MAX_REQUIRED_PERCENT 110.0
/* The wet density a soil can have: mass over volume outside this is a
 * mass in the wrong unit or of another pit (PV_DENSITY_ERR_IMPLAUSIBLE). */
#define PV_DENSITY_MIN_WET_KG_M3 800.0
#define PV_DENSITY_MAX_WET_KG_M3 3000.0

typedef struct pv_density_input {
  double volume_cm3;        /* > 0, the measured pit volume */
  double interval_cm3;      /* >= 0, the volume's +/- interval */
  int has_mass;
  double mass_g;            /* 50 .. 100000: wet mass of the excavated soil */
  int has_moisture;
  double moisture_percent;  /* 0 .. 100: water content, % of dry mass */
  double reference_max_dry_kg_m3; /* 0: none; else 1000 .. 2800 */
} pv_density_input_t;

typedef struct pv_density {
  uint32_t flags;           /* PV_DENSITY_* */
  double wet_kg_m3, wet_low_kg_m3, wet_high_kg_m3;
  double dry_kg_m3, dry_low_kg_m3, dry_high_kg_m3;
  double compaction_percent, compaction_low_percent, compaction_high_percent;
} pv_density_t;

typedef enum pv_density_status {
  /* 0, then 600 .. 699: PV_STATUS_BASE_DENSITY (pitvol/status_codes.h) */
  PV_DENSITY_OK = 0,
  PV_DENSITY_ERR_INVALID_ARGUMENT = 601, /* NULL pointer */
  PV_DENSITY_ERR_VOLUME = 602,           /* volume not > 0 or interval < 0 (or not finite) */
  PV_DENSITY_ERR_MASS = 603,             /* mass outside 50 .. 100000 g */
  PV_DENSITY_ERR_MOISTURE = 604,         /* moisture outside 0 .. 100 % */
  PV_DENSITY_ERR_REFERENCE = 605,        /* reference max dry density outside 1000 .. 2800 kg/m3 */
  PV_DENSITY_ERR_IMPLAUSIBLE = 606       /* mass / volume outside 800 .. 3000 kg/m3 */
} pv_density_status_t;

const char *pv_density_status_name(pv_density_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_density_status_message(pv_density_status_t status);

/* Without a mass: PV_DENSITY_OK with flags 0 (nothing to compute). On an
 * error *out is all zero. */
PV_NODISCARD pv_density_status_t pv_density_compute(const pv_density_input_t *in,
                                                    pv_density_t *out);

/* The test's verdict against a required relative compaction: PASS when
 * the whole compaction range (the volume interval's image) reaches the
 * requirement, FAIL when none of it does, UNDECIDED when the range
 * straddles it. NONE without a compaction or a requirement. */
typedef enum pv_verdict {
  PV_VERDICT_NONE = 0,
  PV_VERDICT_PASS = 1,
  PV_VERDICT_FAIL = 2,
  PV_VERDICT_UNDECIDED = 3
} pv_verdict_t;
/* decides_within_cm3 (may be NULL): for UNDECIDED, the volume interval
 * (+/-) under which this measurement would decide: |V - V*| with V* the
 * volume at which the compaction equals the requirement; 0 otherwise. */
pv_verdict_t pv_density_verdict(const pv_density_t *d, double volume_cm3, double required_percent,
                                double *decides_within_cm3);
const char *pv_verdict_name(pv_verdict_t v); /* "PASS", "FAIL", "UNDECIDED", "" */

/* Unit helpers for screens and reports. */
double pv_density_kg_m3_to_g_cm3(double kg_m3);
double pv_density_kg_m3_to_lb_ft3(double kg_m3);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_DENSITY_H */
