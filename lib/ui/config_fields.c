/* The core's settings with their allowed ranges (pitvol/config_fields.h). */
#include "pitvol/config_fields.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pitvol/user_input.h"

#define U32(f, lo, hi) {#f, offsetof(pv_config_t, f), 0, lo, hi}
#define F32(f, lo, hi) {#f, offsetof(pv_config_t, f), 1, lo, hi}

/* In the order and with the limits of pv_config_validate()
 * (core/session/config.cpp). points_per_layer also has a limit on its
 * product with max_layers, which only the core checks. */
const pv_config_field_t pv_config_fields[] = {
    U32(max_layers, 64, 65536),
    U32(points_per_layer, 64, 1048576),
    U32(level_sample_points, 256, 1048576),
    U32(warmup_points, 256, 16777216),
    F32(layer_mm, 0.1, 2.0),
    F32(bottom_band_ratio, 0.005, 0.5),
    F32(plane_tol_ratio, 0.0001, 0.1),
    U32(ransac_iterations, 16, 100000),
    F32(rim_band_ratio, 0.02, 0.8),
    U32(knn_k, 2, 32),
    F32(thin_base_mm, 0.01, 50.0),
    F32(crescent_range_mm, 1.0, 1000.0),
    F32(crescent_cross_mm, 1.0, 1000.0),
    F32(circle_band_mm, 0.5, 1000.0),
    F32(crescent_relax_mm, 0.0, 1000.0),
    U32(mad_window_early, 3, 256),
    U32(mad_window_late, 3, 256),
    F32(mad_k_early, 0.5, 100.0),
    F32(mad_k_late, 0.5, 100.0),
    F32(mad_split_mm, 0.0, 1000.0),
    F32(max_unseen_share, 0.0, 1.0),
    F32(max_opening_tilt_deg, 0.0, 180.0),
    U32(duplicate_filter, 0, 1),
    U32(surface_floor_points, 256, 16777216),
    U32(surface_theta_bins, 36, 360),
    F32(surface_wall_dz_mm, 0.5, 20.0),
    F32(surface_cell_mm, 0.5, 20.0),
    F32(surface_max_radius_mm, 50.0, 2000.0),
    F32(surface_band_mm, 0.5, 20.0),
    U32(surface_coarse_bins, 0, 1),
};
const size_t pv_config_field_count = sizeof pv_config_fields / sizeof pv_config_fields[0];

const pv_config_field_t *pv_config_field_find(const char *name) {
  for (size_t i = 0; i < pv_config_field_count; ++i) {
    if (strcmp(pv_config_fields[i].name, name) == 0) return &pv_config_fields[i];
  }
  return NULL;
}

pv_ui_status_t pv_config_field_set(pv_config_t *cfg, const char *name, const char *value,
                                   char *err, size_t cap) {
  if (cfg == NULL || name == NULL || value == NULL) {
    snprintf(err, cap, "no setting given");
    return PV_UI_ERR_INVALID_ARGUMENT;
  }
  if (strcmp(name, "method") == 0) {
    if (pv_method_from_name(value, &cfg->method) != PV_OK) {
      snprintf(err, cap, "method = %.40s is not a method (surface, paper or polar)", value);
      return PV_UI_ERR_UNKNOWN_METHOD;
    }
    return PV_UI_OK;
  }
  const pv_config_field_t *f = pv_config_field_find(name);
  if (f == NULL) {
    snprintf(err, cap, "unknown setting '%.60s' (docs/method.md lists them)", name);
    return PV_UI_ERR_UNKNOWN_SETTING;
  }
  char why[160];
  double v = 0;
  const pv_ui_status_t parsed = pv_parse_decimal(value, &v, why, sizeof why);
  if (parsed != PV_UI_OK) {
    snprintf(err, cap, "%s = %s", name, why);
    return parsed;
  }
  if (!f->is_float && v != floor(v)) {
    snprintf(err, cap, "%s = %.40s is not a whole number (allowed: %.9g .. %.9g)", name, value, f->min,
             f->max);
    return PV_UI_ERR_NOT_WHOLE;
  }
  /* The float as the core will hold it decides (0.1 is 0.1f). */
  const double held = f->is_float ? (double)(float)v : v;
  const double lo = f->is_float ? (double)(float)f->min : f->min;
  const double hi = f->is_float ? (double)(float)f->max : f->max;
  if (!(held >= lo && held <= hi)) {
    snprintf(err, cap, "%s = %.40s is outside the allowed %.9g .. %.9g", name, value, f->min, f->max);
    return PV_UI_ERR_OUT_OF_RANGE;
  }
  char *base = (char *)cfg + f->offset;
  if (f->is_float) {
    const float x = (float)v;
    memcpy(base, &x, sizeof x);
  } else {
    const uint32_t x = (uint32_t)v;
    memcpy(base, &x, sizeof x);
  }
  return PV_UI_OK;
}
