/*
 * Numbers a user types (the board's configuration, pitvol-monitor's
 * commands, pitvol-report's options, a pitvol --config file): one parser
 * and one table of plausible ranges, so that every surface refuses the
 * same values with the same one line, and nothing absurd (a mass of
 * 1e308 g, a compaction of 4e305 %) reaches a screen or the result log.
 */
#ifndef PITVOL_USER_INPUT_H
#define PITVOL_USER_INPUT_H

#include <stddef.h>

#include "pitvol/ui_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A decimal number as people write it: an optional sign, digits with at
 * most one decimal point, an optional exponent (1e3). Not hexadecimal
 * (0x10), not inf or nan, no thousands separators; a decimal comma (1,5)
 * is refused with a hint. PV_UI_OK, or PV_UI_ERR_NUMBER_MISSING,
 * _DECIMAL_COMMA, _NOT_A_NUMBER, _OVERFLOW with a one-line reason in err. */
PV_NODISCARD pv_ui_status_t pv_parse_decimal(const char *text, double *out, char *err,
                                             size_t cap);

typedef enum pv_input_kind {
  PV_INPUT_MASS_G = 0,             /* wet mass of the excavated soil */
  PV_INPUT_MOISTURE_PERCENT = 1,   /* water content, % of the dry mass */
  PV_INPUT_MAX_DRY_KG_M3 = 2,      /* Proctor maximum dry density */
  PV_INPUT_REQUIRED_PERCENT = 3,   /* required relative compaction */
  PV_INPUT_KIND_COUNT
} pv_input_kind_t;

typedef struct pv_input_range {
  const char *name;   /* "mass" */
  const char *unit;   /* "g" */
  double min, max;    /* inclusive */
  const char *what;   /* "wet mass of the excavated soil" */
} pv_input_range_t;

/* The plausible range of a kind (pitvol/density.h holds the numbers). */
const pv_input_range_t *pv_input_range_of(pv_input_kind_t kind);

/* PV_UI_OK if v lies in the kind's range, else PV_UI_ERR_OUT_OF_RANGE
 * (or _INVALID_ARGUMENT for an unknown kind) with one line in err:
 * "mass 1e+308 g is outside 50 .. 100000 g (wet mass of the excavated soil)". */
PV_NODISCARD pv_ui_status_t pv_input_check(pv_input_kind_t kind, double v, char *err, size_t cap);

/* pv_parse_decimal, then pv_input_check; their status, err names the kind. */
PV_NODISCARD pv_ui_status_t pv_input_parse(pv_input_kind_t kind, const char *text, double *out,
                                           char *err, size_t cap);

/* Text a user typed for the record (test id, location, operator): printable
 * characters only, at most cap - 1 bytes. PV_UI_OK, or PV_UI_ERR_TOO_LONG,
 * _CONTROL_CHAR (_INVALID_ARGUMENT for NULL) with a reason in err. */
PV_NODISCARD pv_ui_status_t pv_input_text(const char *name, const char *text, char *out,
                                          size_t cap, char *err, size_t errcap);

#ifdef __cplusplus
}
#endif
#endif
