/* The board's configuration file (board_config.h). */
#include "board_config.h"

#include "pitvol/config_fields.h"
#include "pitvol/density.h"
#include "pitvol/user_input.h"
#include "pitvol/serial.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT > PV_STATUS_BASE_BOARD_CONFIG &&
                   PV_BOARD_CONFIG_ERR_CORE < PV_STATUS_BASE_WATCHDOG,
               "pv_board_config_status_t in its range (pitvol/status_codes.h)");

const char *pv_board_config_status_name(pv_board_config_status_t status) {
  switch (status) {
    case PV_BOARD_CONFIG_OK: return "PV_BOARD_CONFIG_OK";
    case PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT: return "PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT";
    case PV_BOARD_CONFIG_ERR_OPEN: return "PV_BOARD_CONFIG_ERR_OPEN";
    case PV_BOARD_CONFIG_ERR_SYNTAX: return "PV_BOARD_CONFIG_ERR_SYNTAX";
    case PV_BOARD_CONFIG_ERR_UNKNOWN_KEY: return "PV_BOARD_CONFIG_ERR_UNKNOWN_KEY";
    case PV_BOARD_CONFIG_ERR_VALUE: return "PV_BOARD_CONFIG_ERR_VALUE";
    case PV_BOARD_CONFIG_ERR_TOO_LONG: return "PV_BOARD_CONFIG_ERR_TOO_LONG";
    case PV_BOARD_CONFIG_ERR_DISPLAY_SIZE: return "PV_BOARD_CONFIG_ERR_DISPLAY_SIZE";
    case PV_BOARD_CONFIG_ERR_CORE: return "PV_BOARD_CONFIG_ERR_CORE";
  }
  return "PV_BOARD_CONFIG_ERR_UNKNOWN";
}

const char *pv_board_config_status_message(pv_board_config_status_t status) {
  switch (status) {
    case PV_BOARD_CONFIG_OK: return "configured";
    case PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT: return "no configuration given; a caller bug";
    case PV_BOARD_CONFIG_ERR_OPEN:
      return "the board configuration file cannot be read; check its path (--config) and "
             "permissions";
    case PV_BOARD_CONFIG_ERR_SYNTAX:
      return "a line of the board configuration is not 'key = value'; fix or comment it out "
             "with '#'";
    case PV_BOARD_CONFIG_ERR_UNKNOWN_KEY:
      return "the board has no such setting; check its spelling against docs/board.md "
             "(core settings: core.<name>, docs/method.md)";
    case PV_BOARD_CONFIG_ERR_VALUE:
      return "a setting's value is of the wrong form or outside its range; set it as the "
             "message names";
    case PV_BOARD_CONFIG_ERR_TOO_LONG: return "a setting's text is too long; shorten it";
    case PV_BOARD_CONFIG_ERR_DISPLAY_SIZE:
      return "the display is smaller than 320 x 240; set display_width and display_height to "
             "at least that";
    case PV_BOARD_CONFIG_ERR_CORE:
      return "the core settings are refused together; go back to the defaults (remove the "
             "core.* lines) and change one at a time";
  }
  return "unknown board configuration status";
}

/* A refused text setting (user_input.h) as the board's status. */
static pv_board_config_status_t from_ui(pv_ui_status_t st) {
  switch (st) {
    case PV_UI_OK: return PV_BOARD_CONFIG_OK;
    case PV_UI_ERR_TOO_LONG: return PV_BOARD_CONFIG_ERR_TOO_LONG;
    case PV_UI_ERR_UNKNOWN_SETTING: return PV_BOARD_CONFIG_ERR_UNKNOWN_KEY;
    case PV_UI_ERR_INVALID_ARGUMENT: return PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT;
    default: return PV_BOARD_CONFIG_ERR_VALUE;
  }
}

void pv_board_config_default(pv_board_config_t *c) {
  memset(c, 0, sizeof *c);
  c->usb_vendor = 0x1209;
  c->usb_product = 0x7050;
  snprintf(c->display, sizeof c->display, "fbdev:/dev/fb0");
  c->display_width = 320;
  c->display_height = 240;
  snprintf(c->input, sizeof c->input, "evdev:/dev/input/event0");
  snprintf(c->serial, sizeof c->serial, "none");
  c->serial_baud = 115200;
  snprintf(c->result_log, sizeof c->result_log, "none");
  c->max_dry_density_kg_m3 = 0;
  snprintf(c->device_id, sizeof c->device_id, "PV-BOARD");
  c->units = PV_UNITS_CM3;
  c->estimate_period_ms = 500;
  pv_config_default(&c->core);
}

static int parse_ulong(const char *v, unsigned long max, unsigned long *out) {
  char *end = NULL;
  errno = 0;
  if (!isdigit((unsigned char)v[0])) return -1;
  const unsigned long x = strtoul(v, &end, 0);
  if (errno != 0 || end == v || *end != '\0' || x > max) return -1;
  *out = x;
  return 0;
}

static int copy_str(char *dst, size_t cap, const char *v) {
  const int n = snprintf(dst, cap, "%s", v);
  return n >= 0 && (size_t)n < cap ? 0 : -1;
}

pv_board_config_status_t pv_board_config_set(pv_board_config_t *c, const char *key,
                                             const char *value, char *err, size_t errcap) {
  if (c == NULL || key == NULL || value == NULL) {
    snprintf(err, errcap, "no setting given");
    return PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT;
  }
  unsigned long u = 0;
  if (strcmp(key, "usb_vendor") == 0 || strcmp(key, "usb_product") == 0) {
    if (parse_ulong(value, 0xFFFF, &u) != 0) {
      snprintf(err, errcap, "%s = %.40s must be a 16-bit number: 0 .. 0xFFFF (e.g. 0x1209)", key, value);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    *(key[4] == 'v' ? &c->usb_vendor : &c->usb_product) = (uint16_t)u;
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "display_width") == 0 || strcmp(key, "display_height") == 0) {
    if (parse_ulong(value, 4096, &u) != 0) {
      snprintf(err, errcap, "%s = %.40s must be a number of pixels: 320 .. 4096", key, value);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    *(key[8] == 'w' ? &c->display_width : &c->display_height) = (uint16_t)u;
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "display") == 0 || strcmp(key, "input") == 0 || strcmp(key, "serial") == 0) {
    char *dst = key[0] == 'd' ? c->display : key[0] == 'i' ? c->input : c->serial;
    if (copy_str(dst, PV_BOARD_PATH_BYTES, value) != 0) {
      snprintf(err, errcap, "%s is longer than %u characters", key, PV_BOARD_PATH_BYTES - 1);
      return PV_BOARD_CONFIG_ERR_TOO_LONG;
    }
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "result_log") == 0) {
    if (copy_str(c->result_log, sizeof c->result_log, value) != 0) {
      snprintf(err, errcap, "result_log is longer than %zu characters", sizeof c->result_log - 1);
      return PV_BOARD_CONFIG_ERR_TOO_LONG;
    }
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "device_id") == 0) {
    return from_ui(
        pv_input_text("device_id", value, c->device_id, sizeof c->device_id, err, errcap));
  }
  if (strcmp(key, "serial_baud") == 0) {
    if (parse_ulong(value, 4000000ul, &u) != 0 || !pv_serial_baud_supported((uint32_t)u)) {
      snprintf(err, errcap, "serial_baud = %.40s must be a standard rate from 9600 to 4000000 (115200)", value);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    c->serial_baud = (uint32_t)u;
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "max_dry_density_kg_m3") == 0) {
    double d = 0;
    char why[200];
    if (strcmp(value, "0") != 0 &&
        pv_input_parse(PV_INPUT_MAX_DRY_KG_M3, value, &d, why, sizeof why) != PV_UI_OK) {
      snprintf(err, errcap, "max_dry_density_kg_m3 = %.40s: %s; or 0 for none", value, why);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    c->max_dry_density_kg_m3 = d;
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "required_compaction_percent") == 0) {
    double d = 0;
    char why[200];
    if (strcmp(value, "0") != 0 &&
        pv_input_parse(PV_INPUT_REQUIRED_PERCENT, value, &d, why, sizeof why) != PV_UI_OK) {
      snprintf(err, errcap, "required_compaction_percent = %.40s: %s; or 0 for none", value, why);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    c->required_compaction_percent = d;
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "location") == 0) {
    return from_ui(pv_input_text("location", value, c->location, sizeof c->location, err, errcap));
  }
  if (strcmp(key, "operator") == 0) {
    return from_ui(pv_input_text("operator", value, c->operator_name, sizeof c->operator_name, err,
                                 errcap));
  }
  if (strcmp(key, "units") == 0) {
    if (strcmp(value, "cm3") == 0) {
      c->units = PV_UNITS_CM3;
    } else if (strcmp(value, "l") == 0) {
      c->units = PV_UNITS_LITRE;
    } else {
      snprintf(err, errcap, "units = %.40s must be cm3 or l", value);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    return PV_BOARD_CONFIG_OK;
  }
  if (strcmp(key, "estimate_period_ms") == 0) {
    if (parse_ulong(value, 60000, &u) != 0 || u < 100) {
      snprintf(err, errcap, "estimate_period_ms = %.40s is outside 100 .. 60000", value);
      return PV_BOARD_CONFIG_ERR_VALUE;
    }
    c->estimate_period_ms = (uint32_t)u;
    return PV_BOARD_CONFIG_OK;
  }
  if (strncmp(key, "core.", 5) == 0) {
    char why[200];
    const pv_ui_status_t st = pv_config_field_set(&c->core, key + 5, value, why, sizeof why);
    if (st != PV_UI_OK) snprintf(err, errcap, "core.%s", why);
    return from_ui(st);
  }
  snprintf(err, errcap, "unknown key '%s'", key);
  return PV_BOARD_CONFIG_ERR_UNKNOWN_KEY;
}

static char *trim(char *s) {
  while (*s == ' ' || *s == '\t') ++s;
  size_t n = strlen(s);
  while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n')) {
    s[--n] = '\0';
  }
  return s;
}

pv_board_config_status_t pv_board_config_load(pv_board_config_t *c, const char *path, char *err,
                                              size_t errcap) {
  if (c == NULL || path == NULL) {
    snprintf(err, errcap, "no board configuration given");
    return PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT;
  }
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    snprintf(err, errcap, "%s: cannot open the board configuration: %s", path, strerror(errno));
    return PV_BOARD_CONFIG_ERR_OPEN;
  }
  char line[512], why[256];
  int lineno = 0;
  pv_board_config_status_t rc = PV_BOARD_CONFIG_OK;
  while (rc == PV_BOARD_CONFIG_OK && fgets(line, sizeof line, f) != NULL) {
    ++lineno;
    char *hash = strchr(line, '#');
    if (hash != NULL) *hash = '\0';
    char *s = trim(line);
    if (*s == '\0') continue;
    char *eq = strchr(s, '=');
    if (eq == NULL) {
      snprintf(err, errcap, "%s:%d: expected 'key = value'", path, lineno);
      rc = PV_BOARD_CONFIG_ERR_SYNTAX;
      break;
    }
    *eq = '\0';
    rc = pv_board_config_set(c, trim(s), trim(eq + 1), why, sizeof why);
    if (rc != PV_BOARD_CONFIG_OK) snprintf(err, errcap, "%s:%d: %s", path, lineno, why);
  }
  fclose(f);
  return rc;
}

pv_board_config_status_t pv_board_config_check(const pv_board_config_t *c, char *err,
                                               size_t errcap) {
  if (c == NULL) {
    snprintf(err, errcap, "no board configuration given");
    return PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT;
  }
  if (c->display_width < 320 || c->display_height < 240) {
    snprintf(err, errcap, "display_width x display_height must be at least 320 x 240");
    return PV_BOARD_CONFIG_ERR_DISPLAY_SIZE;
  }
  const char *field = NULL;
  if (pv_config_validate(&c->core, &field) != PV_OK) {
    snprintf(err, errcap, "core.%s is out of range", field != NULL ? field : "?");
    return PV_BOARD_CONFIG_ERR_CORE;
  }
  return PV_BOARD_CONFIG_OK;
}
