/* In-place density and relative compaction (see pitvol/density.h). */
#include "pitvol/density.h"

#include <math.h>
#include <string.h>

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
      return "the soil mass must be more than 0 g; weigh the excavated soil and enter "
             "its mass in grams";
    case PV_DENSITY_ERR_MOISTURE:
      return "the moisture content must be 0 to 500 % of the dry mass; enter it in %";
    case PV_DENSITY_ERR_REFERENCE:
      return "the reference maximum dry density must be 500 to 3500 kg/m3; check the "
             "configuration (a value in g/cm3 must be multiplied by 1000)";
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
  if (!isfinite(in->mass_g) || !(in->mass_g > 0.0)) return PV_DENSITY_ERR_MASS;
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
