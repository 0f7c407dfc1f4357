/*
 * The board's buttons: start/stop, enter, back.
 *
 * Backends, chosen by a spec string (board config key `input`):
 *   "evdev:/dev/input/eventN"  Linux evdev (gpio-keys on the board; any
 *                   keyboard on a host). Key presses (value 1) map to:
 *                     start/stop  KEY_RECORD, KEY_PLAYPAUSE, KEY_SPACE, KEY_S
 *                     enter       KEY_ENTER, KEY_OK, KEY_SELECT, KEY_KPENTER
 *                     back        KEY_BACK, KEY_ESC, KEY_BACKSPACE, KEY_B
 *                   other keys, releases and autorepeat are ignored.
 *   "pipe:PATH"     a named pipe (created if missing) carrying one word per
 *                   line: start, stop (both the start/stop button), enter,
 *                   back; unknown words are reported and ignored. Opened
 *                   read-write so it never reports end-of-file when a
 *                   writer goes away. For host runs and tests.
 *   "none"          no buttons (a serial link may still drive the board).
 * The caller polls pv_input_fd() for POLLIN and calls pv_input_read().
 * Nothing is allocated after open.
 */
#ifndef PITVOL_INPUT_H
#define PITVOL_INPUT_H

#include <stddef.h>

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pv_key {
  PV_KEY_NONE = 0,
  PV_KEY_START_STOP = 1,
  PV_KEY_ENTER = 2,
  PV_KEY_BACK = 3
} pv_key_t;

/* 0, then 751 .. 799: PV_STATUS_BASE_INPUT (pitvol/status_codes.h). */
typedef enum pv_input_status {
  PV_INPUT_OK = 0,
  PV_INPUT_ERR_INVALID_ARGUMENT = 751, /* NULL */
  PV_INPUT_ERR_SPEC = 752,             /* the spec names no backend (evdev:, pipe:, none) */
  PV_INPUT_ERR_NO_MEMORY = 753,
  PV_INPUT_ERR_OPEN = 754,             /* the evdev device or the named pipe cannot be opened */
  PV_INPUT_ERR_PIPE = 755,             /* the named pipe cannot be created */
  PV_INPUT_ERR_GONE = 756              /* the evdev device went away (unplugged, read error) */
} pv_input_status_t;

/* The symbol ("PV_INPUT_ERR_OPEN"). Never NULL. */
const char *pv_input_status_name(pv_input_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_input_status_message(pv_input_status_t status);

typedef struct pv_input pv_input_t;

/* PV_INPUT_OK, or PV_INPUT_ERR_INVALID_ARGUMENT, _SPEC, _NO_MEMORY, _OPEN,
 * _PIPE with one sentence in err that adds the device and the system's
 * reason. */
PV_NODISCARD pv_input_status_t pv_input_open(pv_input_t **out, const char *spec, char *err,
                                             size_t errcap);
/* The descriptor to poll for POLLIN, or -1 for "none". */
int pv_input_fd(const pv_input_t *in);
/* Reads what is pending without blocking; writes up to cap keys and their
 * number to *count. PV_INPUT_OK, or PV_INPUT_ERR_GONE if the device went
 * away (err says how; *count holds the keys read before). */
PV_NODISCARD pv_input_status_t pv_input_read(pv_input_t *in, pv_key_t *keys, size_t cap,
                                             size_t *count, char *err, size_t errcap);
void pv_input_close(pv_input_t *in);
const char *pv_key_name(pv_key_t k);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_INPUT_H */
