/* Numbers and text a user types (pitvol/user_input.h). */
#include "pitvol/user_input.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pitvol/density.h"

int pv_parse_decimal(const char *text, double *out, char *err, size_t cap) {
  const char *p = text;
  if (p == NULL || *p == '\0') {
    snprintf(err, cap, "a number is missing");
    return -1;
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
      return -1;
    } else {
      snprintf(err, cap, "'%.40s' is not a decimal number", text);
      return -1;
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
    return -1;
  }
  errno = 0;
  char *end = NULL;
  const double v = strtod(text, &end);
  if (end == text || *end != '\0' || !isfinite(v) || errno == ERANGE) {
    snprintf(err, cap, "'%.40s' is out of any sensible range", text);
    return -1;
  }
  *out = v;
  return 0;
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

int pv_input_check(pv_input_kind_t kind, double v, char *err, size_t cap) {
  const pv_input_range_t *r = pv_input_range_of(kind);
  if (r == NULL) {
    snprintf(err, cap, "unknown input");
    return -1;
  }
  if (isfinite(v) && v >= r->min && v <= r->max) return 0;
  snprintf(err, cap, "%s %.6g %s is outside %g .. %g %s (%s)", r->name, v, r->unit, r->min, r->max,
           r->unit, r->what);
  return -1;
}

int pv_input_parse(pv_input_kind_t kind, const char *text, double *out, char *err, size_t cap) {
  const pv_input_range_t *r = pv_input_range_of(kind);
  char why[160];
  double v = 0;
  if (r == NULL) {
    snprintf(err, cap, "unknown input");
    return -1;
  }
  if (pv_parse_decimal(text, &v, why, sizeof why) != 0) {
    snprintf(err, cap, "%s: %s", r->name, why);
    return -1;
  }
  if (pv_input_check(kind, v, err, cap) != 0) return -1;
  *out = v;
  return 0;
}

int pv_input_text(const char *name, const char *text, char *out, size_t cap, char *err,
                  size_t errcap) {
  const size_t n = strlen(text);
  if (n + 1 > cap) {
    snprintf(err, errcap, "%s is longer than %zu characters", name, cap - 1);
    return -1;
  }
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = (unsigned char)text[i];
    /* Control characters would reach terminals, screens and the log. */
    if (c < 0x20 || c == 0x7f) {
      snprintf(err, errcap, "%s holds a control character (byte %zu); use printable text", name, i + 1);
      return -1;
    }
  }
  memcpy(out, text, n + 1);
  return 0;
}
