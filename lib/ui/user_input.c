/* Numbers and text a user types (pitvol/user_input.h). */
#include "pitvol/user_input.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pitvol/density.h"

_Static_assert(PV_UI_ERR_INVALID_ARGUMENT > PV_STATUS_BASE_UI &&
                   PV_UI_ERR_UNKNOWN_METHOD < PV_STATUS_BASE_BOARD_CONFIG,
               "pv_ui_status_t in its range (pitvol/status_codes.h)");

const char *pv_ui_status_name(pv_ui_status_t status) {
  switch (status) {
    case PV_UI_OK: return "PV_UI_OK";
    case PV_UI_ERR_INVALID_ARGUMENT: return "PV_UI_ERR_INVALID_ARGUMENT";
    case PV_UI_ERR_NUMBER_MISSING: return "PV_UI_ERR_NUMBER_MISSING";
    case PV_UI_ERR_DECIMAL_COMMA: return "PV_UI_ERR_DECIMAL_COMMA";
    case PV_UI_ERR_NOT_A_NUMBER: return "PV_UI_ERR_NOT_A_NUMBER";
    case PV_UI_ERR_OVERFLOW: return "PV_UI_ERR_OVERFLOW";
    case PV_UI_ERR_OUT_OF_RANGE: return "PV_UI_ERR_OUT_OF_RANGE";
    case PV_UI_ERR_NOT_WHOLE: return "PV_UI_ERR_NOT_WHOLE";
    case PV_UI_ERR_TOO_LONG: return "PV_UI_ERR_TOO_LONG";
    case PV_UI_ERR_CONTROL_CHAR: return "PV_UI_ERR_CONTROL_CHAR";
    case PV_UI_ERR_UNKNOWN_SETTING: return "PV_UI_ERR_UNKNOWN_SETTING";
    case PV_UI_ERR_UNKNOWN_METHOD: return "PV_UI_ERR_UNKNOWN_METHOD";
  }
  return "PV_UI_ERR_UNKNOWN";
}

const char *pv_ui_status_message(pv_ui_status_t status) {
  switch (status) {
    case PV_UI_OK: return "accepted";
    case PV_UI_ERR_INVALID_ARGUMENT: return "no value or an unknown kind of value; a caller bug";
    case PV_UI_ERR_NUMBER_MISSING: return "a number is missing; type one";
    case PV_UI_ERR_DECIMAL_COMMA:
      return "a decimal comma is not read; write decimals with a point (1.5, not 1,5)";
    case PV_UI_ERR_NOT_A_NUMBER:
      return "not a decimal number; type digits with at most one point and an optional "
             "exponent (1850, 0.5, 1e3), without units or thousands separators";
    case PV_UI_ERR_OVERFLOW: return "the number is out of any sensible range; check its digits";
    case PV_UI_ERR_OUT_OF_RANGE:
      return "the number is outside the range allowed for it; check its unit and type a "
             "value in the range named";
    case PV_UI_ERR_NOT_WHOLE: return "this setting is a whole number; type it without a fraction";
    case PV_UI_ERR_TOO_LONG: return "the text is longer than its field; shorten it";
    case PV_UI_ERR_CONTROL_CHAR:
      return "the text holds a control character; type printable text only";
    case PV_UI_ERR_UNKNOWN_SETTING:
      return "no such setting; check its spelling against docs/method.md";
    case PV_UI_ERR_UNKNOWN_METHOD: return "no such method; use surface, paper or polar";
  }
  return "unknown ui status";
}

pv_ui_status_t pv_parse_decimal(const char *text, double *out, char *err, size_t cap) {
  const char *p = text;
  if (out == NULL) {
    snprintf(err, cap, "no place for the number");
    return PV_UI_ERR_INVALID_ARGUMENT;
  }
  if (p == NULL || *p == '\0') {
    snprintf(err, cap, "a number is missing");
    return PV_UI_ERR_NUMBER_MISSING;
  }
  if (*p == '+' || *p == '-') ++p;
  int digits = 0, points = 0;
  for (; *p != '\0' && *p != 'e' && *p != 'E'; ++p) {
    if (isdigit((unsigned char)*p)) {
      ++digits;
    } else if (*p == '.') {
      ++points;
    } else if (*p == ',') {
      snprintf(err, cap, "'%.40s' is not a number: write decimals with a point (1.5, not 1,5)", text);
      return PV_UI_ERR_DECIMAL_COMMA;
    } else {
      snprintf(err, cap, "'%.40s' is not a decimal number", text);
      return PV_UI_ERR_NOT_A_NUMBER;
    }
  }
  if (*p == 'e' || *p == 'E') {
    ++p;
    if (*p == '+' || *p == '-') ++p;
    if (!isdigit((unsigned char)*p)) digits = 0;
    while (isdigit((unsigned char)*p)) ++p;
    if (*p != '\0') digits = 0;
  }
  if (digits == 0 || points > 1) {
    snprintf(err, cap, "'%.40s' is not a decimal number", text);
    return PV_UI_ERR_NOT_A_NUMBER;
  }
  errno = 0;
  char *end = NULL;
  const double v = strtod(text, &end);
  if (end == text || *end != '\0' || !isfinite(v) || errno == ERANGE) {
    snprintf(err, cap, "'%.40s' is out of any sensible range", text);
    return PV_UI_ERR_OVERFLOW;
  }
  *out = v;
  return PV_UI_OK;
}

static const pv_input_range_t kRanges[PV_INPUT_KIND_COUNT] = {
    {"mass", "g", PV_DENSITY_MIN_MASS_G, PV_DENSITY_MAX_MASS_G, "wet mass of the excavated soil"},
    {"moisture", "%", 0.0, PV_DENSITY_MAX_MOISTURE_PERCENT, "water content, % of the dry mass"},
    {"max dry density", "kg/m3", PV_DENSITY_MIN_REFERENCE_KG_M3, PV_DENSITY_MAX_REFERENCE_KG_M3,
     "Proctor maximum dry density; a value in g/cm3 times 1000"},
    {"required compaction", "%", PV_DENSITY_MIN_REQUIRED_PERCENT, PV_DENSITY_MAX_REQUIRED_PERCENT,
     "relative compaction the specification requires"},
};

const pv_input_range_t *pv_input_range_of(pv_input_kind_t kind) {
  return (unsigned)kind < PV_INPUT_KIND_COUNT ? &kRanges[kind] : NULL;
}

pv_ui_status_t pv_input_check(pv_input_kind_t kind, double v, char *err, size_t cap) {
  const pv_input_range_t *r = pv_input_range_of(kind);
  if (r == NULL) {
    snprintf(err, cap, "unknown input");
    return PV_UI_ERR_INVALID_ARGUMENT;
  }
  if (isfinite(v) && v >= r->min && v <= r->max) return PV_UI_OK;
  snprintf(err, cap, "%s %.6g %s is outside %g .. %g %s (%s)", r->name, v, r->unit, r->min, r->max,
           r->unit, r->what);
  return PV_UI_ERR_OUT_OF_RANGE;
}

pv_ui_status_t pv_input_parse(pv_input_kind_t kind, const char *text, double *out, char *err,
                              size_t cap) {
  const pv_input_range_t *r = pv_input_range_of(kind);
  char why[160];
  double v = 0;
  if (r == NULL || out == NULL) {
    snprintf(err, cap, "unknown input");
    return PV_UI_ERR_INVALID_ARGUMENT;
  }
  const pv_ui_status_t parsed = pv_parse_decimal(text, &v, why, sizeof why);
  if (parsed != PV_UI_OK) {
    snprintf(err, cap, "%s: %s", r->name, why);
    return parsed;
  }
  const pv_ui_status_t checked = pv_input_check(kind, v, err, cap);
  if (checked != PV_UI_OK) return checked;
  *out = v;
  return PV_UI_OK;
}

pv_ui_status_t pv_input_text(const char *name, const char *text, char *out, size_t cap, char *err,
                             size_t errcap) {
  if (name == NULL || text == NULL || out == NULL || cap == 0) {
    snprintf(err, errcap, "no text given");
    return PV_UI_ERR_INVALID_ARGUMENT;
  }
  const size_t n = strlen(text);
  if (n + 1 > cap) {
    snprintf(err, errcap, "%s is longer than %zu characters", name, cap - 1);
    return PV_UI_ERR_TOO_LONG;
  }
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = (unsigned char)text[i];
    /* Control characters would reach terminals, screens and the log. */
    if (c < 0x20 || c == 0x7f) {
      snprintf(err, errcap, "%s holds a control character (byte %zu); use printable text", name, i + 1);
      return PV_UI_ERR_CONTROL_CHAR;
    }
  }
  memcpy(out, text, n + 1);
  return PV_UI_OK;
}
