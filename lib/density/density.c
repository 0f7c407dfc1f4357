/* In-place density and relative compaction (see pitvol/density.h). */
#include "pitvol/density.h"

#include <math.h>
#include <string.h>

_Static_assert(PV_DENSITY_ERR_INVALID_ARGUMENT > PV_STATUS_BASE_DENSITY &&
                   PV_DENSITY_ERR_IMPLAUSIBLE < PV_STATUS_BASE_DENSITY + PV_STATUS_RANGE,
               "pv_density_status_t in its range (pitvol/status_codes.h)");

/* 1 g/cm3 = 1000 kg/m3. */
#define KG_M3_PER_G_CM3 1000.0
/* 1 lb/ft3 = 0.45359237 kg / 0.028316846592 m3 = 16.018463373960138 kg/m3. */
#define KG_M3_PER_LB_FT3 16.018463373960138

const char *pv_density_status_name(pv_density_status_t status) {
  switch (status) {
    case PV_DENSITY_OK: return "PV_DENSITY_OK";
    case PV_DENSITY_ERR_INVALID_ARGUMENT: return "PV_DENSITY_ERR_INVALID_ARGUMENT";
    case PV_DENSITY_ERR_VOLUME: return "PV_DENSITY_ERR_VOLUME";
    case PV_DENSITY_ERR_MASS: return "PV_DENSITY_ERR_MASS";
    case PV_DENSITY_ERR_MOISTURE: return "PV_DENSITY_ERR_MOISTURE";
    case PV_DENSITY_ERR_REFERENCE: return "PV_DENSITY_ERR_REFERENCE";
    case PV_DENSITY_ERR_IMPLAUSIBLE: return "PV_DENSITY_ERR_IMPLAUSIBLE";
  }
  return "PV_DENSITY_ERR_UNKNOWN";
}

const char *pv_density_status_message(pv_density_status_t status) {
  switch (status) {
    case PV_DENSITY_OK: return "computed";
    case PV_DENSITY_ERR_INVALID_ARGUMENT: return "a NULL pointer was passed; a caller bug";
    case PV_DENSITY_ERR_VOLUME:
      return "there is no valid volume to divide by; measure the pit first";
    case PV_DENSITY_ERR_MASS:
      return "the soil mass must be 50 to 100000 g; weigh the excavated soil and enter "
             "its mass in grams";
    case PV_DENSITY_ERR_MOISTURE:
      return "the moisture content must be 0 to 100 % of the dry mass; enter it in %";
    case PV_DENSITY_ERR_REFERENCE:
      return "the reference maximum dry density must be 1000 to 2800 kg/m3; check the "
             "configuration (a value in g/cm3 must be multiplied by 1000)";
    case PV_DENSITY_ERR_IMPLAUSIBLE:
      return "the mass over the measured volume is no soil's density (800 to 3000 kg/m3); "
             "check that the mass is in grams and belongs to this pit";
  }
  return "unknown density status";
}

double pv_density_kg_m3_to_g_cm3(double kg_m3) { return kg_m3 / KG_M3_PER_G_CM3; }
double pv_density_kg_m3_to_lb_ft3(double kg_m3) { return kg_m3 / KG_M3_PER_LB_FT3; }

pv_density_status_t pv_density_compute(const pv_density_input_t *in, pv_density_t *out) {
  if (!in || !out) return PV_DENSITY_ERR_INVALID_ARGUMENT;
  memset(out, 0, sizeof *out);
  const double v = in->volume_cm3, dv = in->interval_cm3;
  if (!isfinite(v) || !(v > 0.0) || !isfinite(dv) || !(dv >= 0.0)) return PV_DENSITY_ERR_VOLUME;
  if (!in->has_mass) return PV_DENSITY_OK;
  if (!isfinite(in->mass_g) || !(in->mass_g >= PV_DENSITY_MIN_MASS_G) ||
      in->mass_g > PV_DENSITY_MAX_MASS_G)
    return PV_DENSITY_ERR_MASS;
  if (in->has_moisture &&
      (!isfinite(in->moisture_percent) || !(in->moisture_percent >= 0.0) ||
       in->moisture_percent > PV_DENSITY_MAX_MOISTURE_PERCENT))
    return PV_DENSITY_ERR_MOISTURE;
  const double ref = in->reference_max_dry_kg_m3;
  if (ref != 0.0 && (!isfinite(ref) || ref < PV_DENSITY_MIN_REFERENCE_KG_M3 ||
                     ref > PV_DENSITY_MAX_REFERENCE_KG_M3))
    return PV_DENSITY_ERR_REFERENCE;

  pv_density_t d;
  memset(&d, 0, sizeof d);
  const int bounded = dv < v;
  const double m = in->mass_g;
  const double wet = m / v * KG_M3_PER_G_CM3;
  if (!(wet >= PV_DENSITY_MIN_WET_KG_M3) || wet > PV_DENSITY_MAX_WET_KG_M3) return PV_DENSITY_ERR_IMPLAUSIBLE;
  d.flags = PV_DENSITY_WET | (bounded ? 0u : PV_DENSITY_UNBOUNDED);
  d.wet_kg_m3 = m / v * KG_M3_PER_G_CM3;
  d.wet_low_kg_m3 = m / (v + dv) * KG_M3_PER_G_CM3;
  d.wet_high_kg_m3 = bounded ? m / (v - dv) * KG_M3_PER_G_CM3 : 0.0;
  if (in->has_moisture) {
    const double k = 1.0 + in->moisture_percent / 100.0;
    d.flags |= PV_DENSITY_DRY;
    d.dry_kg_m3 = d.wet_kg_m3 / k;
    d.dry_low_kg_m3 = d.wet_low_kg_m3 / k;
    d.dry_high_kg_m3 = d.wet_high_kg_m3 / k;
    if (ref != 0.0) {
      d.flags |= PV_DENSITY_COMPACTION;
      d.compaction_percent = d.dry_kg_m3 / ref * 100.0;
      d.compaction_low_percent = d.dry_low_kg_m3 / ref * 100.0;
      d.compaction_high_percent = d.dry_high_kg_m3 / ref * 100.0;
    }
  }
  *out = d;
  return PV_DENSITY_OK;
}

pv_verdict_t pv_density_verdict(const pv_density_t *d, double volume_cm3, double required_percent,
                                double *decides_within_cm3) {
  if (decides_within_cm3 != NULL) *decides_within_cm3 = 0.0;
  if (d == NULL || !(d->flags & PV_DENSITY_COMPACTION) || !(required_percent > 0.0)) return PV_VERDICT_NONE;
  const int open = (d->flags & PV_DENSITY_UNBOUNDED) != 0;
  if (d->compaction_low_percent >= required_percent) return PV_VERDICT_PASS;
  if (!open && d->compaction_high_percent < required_percent) return PV_VERDICT_FAIL;
  /* The compaction is inversely proportional to the volume: it equals the
   * requirement at V* = V * RC / required. */
  if (decides_within_cm3 != NULL && isfinite(volume_cm3)) {
    *decides_within_cm3 = fabs(volume_cm3 - volume_cm3 * d->compaction_percent / required_percent);
  }
  return PV_VERDICT_UNDECIDED;
}

const char *pv_verdict_name(pv_verdict_t v) {
  switch (v) {
    case PV_VERDICT_PASS: return "PASS";
    case PV_VERDICT_FAIL: return "FAIL";
    case PV_VERDICT_UNDECIDED: return "UNDECIDED";
    case PV_VERDICT_NONE: break;
  }
  return "";
}
