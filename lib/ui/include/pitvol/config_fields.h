/*
 * The core's settings (pv_config_t) by the names docs/method.md uses, with
 * the range pv_config_validate() allows each one, for every file that
 * sets them: `pitvol measure --config FILE` and the board's configuration
 * (`core.<name>`). A refused value is one line that names the key, the
 * value and the allowed range. tests/firmware/board checks the ranges against
 * pv_config_validate() at both ends of each.
 */
#ifndef PITVOL_CONFIG_FIELDS_H
#define PITVOL_CONFIG_FIELDS_H

#include <stddef.h>

#include "pitvol/pitvol.h"
#include "pitvol/ui_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pv_config_field {
  const char *name;
  size_t offset;    /* into pv_config_t */
  int is_float;     /* float, else uint32_t (a whole number) */
  double min, max;  /* the range pv_config_validate() allows */
} pv_config_field_t;

extern const pv_config_field_t pv_config_fields[];
extern const size_t pv_config_field_count;

/* NULL if name is not a setting ("method" is not in the table). */
const pv_config_field_t *pv_config_field_find(const char *name);

/* Sets one setting from its text ("method" = surface|paper|polar too).
 * PV_UI_OK, or the fault with one line in err: PV_UI_ERR_UNKNOWN_SETTING
 * ("unknown setting 'x'"), _UNKNOWN_METHOD, _OUT_OF_RANGE ("layer_mm = 9
 * is outside 0.1 .. 2"), _NOT_WHOLE, or pv_parse_decimal's ("'0,5' is not
 * a number: write decimals with a point"). */
PV_NODISCARD pv_ui_status_t pv_config_field_set(pv_config_t *cfg, const char *name,
                                                const char *value, char *err, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
