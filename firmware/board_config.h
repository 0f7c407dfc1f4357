/*
 * The board's configuration file: `key = value` lines, '#' comments.
 *
 *   usb_vendor = 0x1209          scanner USB ids (docs/protocol/usb.md)
 *   usb_product = 0x7050
 *   display = fbdev:/dev/fb0     or png:DIR (host, tests); display.h
 *   display_width = 320          canvas size in pixels (>= 320 x 240)
 *   display_height = 240
 *   input = evdev:/dev/input/event0   or pipe:PATH, none; input.h
 *   serial = /dev/ttyS1          the tablet/logger link, or none
 *   serial_baud = 115200         its rate (9600 .. 4000000, standard rates)
 *   result_log = /var/lib/pitvol/results   the result log's directory, or none
 *   max_dry_density_kg_m3 = 1850 reference for relative compaction (0: none)
 *   required_compaction_percent = 95   the verdict's requirement (0: none)
 *   location = STA 1+250         the test record's location, operator
 *   operator = J. Okafor         (also set over the link: SetRecord)
 *   device_id = PV-0001          sent in the link's Hello
 *   units = cm3                  volume shown in cm3 or l
 *   estimate_period_ms = 500     live estimate while scanning
 *   core.<field> = value         any pv_config_t field by its name
 *                                (core.method = paper, core.layer_mm ...)
 * Unknown keys and bad values are errors that name the line.
 */
#ifndef PV_BOARD_CONFIG_H
#define PV_BOARD_CONFIG_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/pitvol.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_BOARD_PATH_BYTES 256u

typedef enum pv_board_units { PV_UNITS_CM3 = 0, PV_UNITS_LITRE = 1 } pv_board_units_t;

typedef struct pv_board_config {
  uint16_t usb_vendor, usb_product;
  char display[PV_BOARD_PATH_BYTES];
  uint16_t display_width, display_height;
  char input[PV_BOARD_PATH_BYTES];
  char serial[PV_BOARD_PATH_BYTES];
  uint32_t serial_baud;
  char result_log[PV_BOARD_PATH_BYTES];
  double max_dry_density_kg_m3; /* 0: no compaction */
  double required_compaction_percent; /* 0: no verdict */
  char location[48];             /* the test record (Record.location) */
  char operator_name[32];
  char device_id[24];   /* Hello.device_id: at most 23 characters */
  pv_board_units_t units;
  uint32_t estimate_period_ms;
  pv_config_t core;
} pv_board_config_t;

/* 0, then 851 .. 899: PV_STATUS_BASE_BOARD_CONFIG (pitvol/status_codes.h). */
typedef enum pv_board_config_status {
  PV_BOARD_CONFIG_OK = 0,
  PV_BOARD_CONFIG_ERR_INVALID_ARGUMENT = 851, /* NULL */
  PV_BOARD_CONFIG_ERR_OPEN = 852,             /* the file cannot be opened */
  PV_BOARD_CONFIG_ERR_SYNTAX = 853,           /* a line that is not `key = value` */
  PV_BOARD_CONFIG_ERR_UNKNOWN_KEY = 854,      /* a key (or core.<field>) the board does not have */
  PV_BOARD_CONFIG_ERR_VALUE = 855,            /* a value of the wrong form or outside its range */
  PV_BOARD_CONFIG_ERR_TOO_LONG = 856,         /* a path or a text longer than its field */
  PV_BOARD_CONFIG_ERR_DISPLAY_SIZE = 857,     /* display smaller than 320 x 240 */
  PV_BOARD_CONFIG_ERR_CORE = 858              /* the core's settings together are refused */
} pv_board_config_status_t;

/* The symbol ("PV_BOARD_CONFIG_ERR_VALUE"). Never NULL. */
const char *pv_board_config_status_name(pv_board_config_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_board_config_status_message(pv_board_config_status_t status);

/* Board defaults (fbdev:/dev/fb0, evdev:/dev/input/event0, 320x240, cm3)
 * and the core's defaults. */
void pv_board_config_default(pv_board_config_t *c);
/* Applies one `key = value`. PV_BOARD_CONFIG_OK, or _UNKNOWN_KEY, _VALUE,
 * _TOO_LONG with a reason in err (the key, the value, the range). */
PV_NODISCARD pv_board_config_status_t pv_board_config_set(pv_board_config_t *c, const char *key,
                                                          const char *value, char *err,
                                                          size_t errcap);
/* Reads a file on top of what c holds. PV_BOARD_CONFIG_OK, _OPEN, _SYNTAX
 * or the first bad line's pv_board_config_set status, with
 * "path:line: reason" in err. */
PV_NODISCARD pv_board_config_status_t pv_board_config_load(pv_board_config_t *c, const char *path,
                                                           char *err, size_t errcap);
/* Checks the whole configuration (core included). PV_BOARD_CONFIG_OK,
 * _DISPLAY_SIZE or _CORE with a reason in err. */
PV_NODISCARD pv_board_config_status_t pv_board_config_check(const pv_board_config_t *c, char *err,
                                                            size_t errcap);

#ifdef __cplusplus
}
#endif
#endif
