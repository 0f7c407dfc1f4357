/* Input driver front (input.h): opens the backend named by the spec. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "input_backend.h"

_Static_assert(PV_INPUT_ERR_INVALID_ARGUMENT > PV_STATUS_BASE_INPUT &&
                   PV_INPUT_ERR_GONE < PV_STATUS_BASE_UI,
               "pv_input_status_t in its range (pitvol/status_codes.h)");

const char *pv_input_status_name(pv_input_status_t status) {
  switch (status) {
    case PV_INPUT_OK: return "PV_INPUT_OK";
    case PV_INPUT_ERR_INVALID_ARGUMENT: return "PV_INPUT_ERR_INVALID_ARGUMENT";
    case PV_INPUT_ERR_SPEC: return "PV_INPUT_ERR_SPEC";
    case PV_INPUT_ERR_NO_MEMORY: return "PV_INPUT_ERR_NO_MEMORY";
    case PV_INPUT_ERR_OPEN: return "PV_INPUT_ERR_OPEN";
    case PV_INPUT_ERR_PIPE: return "PV_INPUT_ERR_PIPE";
    case PV_INPUT_ERR_GONE: return "PV_INPUT_ERR_GONE";
  }
  return "PV_INPUT_ERR_UNKNOWN";
}

const char *pv_input_status_message(pv_input_status_t status) {
  switch (status) {
    case PV_INPUT_OK: return "ready";
    case PV_INPUT_ERR_INVALID_ARGUMENT:
      return "the buttons were opened without a spec; a caller bug";
    case PV_INPUT_ERR_SPEC:
      return "the input setting names no buttons: use evdev:/dev/input/eventN on the board, "
             "pipe:PATH on a host, or none";
    case PV_INPUT_ERR_NO_MEMORY: return "no memory for the buttons; restart the board";
    case PV_INPUT_ERR_OPEN:
      return "the buttons' device cannot be opened; check the input setting and its "
             "permissions (the input group)";
    case PV_INPUT_ERR_PIPE:
      return "the button pipe cannot be created; check that its directory exists and is "
             "writable";
    case PV_INPUT_ERR_GONE:
      return "the buttons' device went away; check its cable or driver, then restart the "
             "board (a serial link can still drive it)";
  }
  return "unknown input status";
}

const char *pv_key_name(pv_key_t k) {
  switch (k) {
    case PV_KEY_START_STOP: return "start/stop";
    case PV_KEY_ENTER: return "enter";
    case PV_KEY_BACK: return "back";
    case PV_KEY_NONE: break;
  }
  return "none";
}

pv_input_status_t pv_input_open(pv_input_t **out, const char *spec, char *err, size_t errcap) {
  if (out == NULL || spec == NULL) {
    snprintf(err, errcap, "input: no spec given");
    return PV_INPUT_ERR_INVALID_ARGUMENT;
  }
  *out = NULL;
  struct pv_input *in = (struct pv_input *)calloc(1, sizeof *in);
  if (in == NULL) {
    snprintf(err, errcap, "input: out of memory");
    return PV_INPUT_ERR_NO_MEMORY;
  }
  in->fd = -1;
  if (strcmp(spec, "none") == 0) {
    *out = in;
    return PV_INPUT_OK;
  }
  if (strncmp(spec, "evdev:", 6) == 0) {
    in->kind = 1;
    in->fd = open(spec + 6, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (in->fd < 0) {
      snprintf(err, errcap, "cannot open buttons %s: %s (check the input config and permissions)",
               spec + 6, strerror(errno));
      free(in);
      return PV_INPUT_ERR_OPEN;
    }
  } else if (strncmp(spec, "pipe:", 5) == 0) {
    in->kind = 2;
    if (mkfifo(spec + 5, 0600) != 0 && errno != EEXIST) {
      snprintf(err, errcap, "cannot create the button pipe %s: %s", spec + 5, strerror(errno));
      free(in);
      return PV_INPUT_ERR_PIPE;
    }
    /* Read-write: we are a writer ourselves, so no EOF/POLLHUP when the
     * last outside writer closes. */
    in->fd = open(spec + 5, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (in->fd < 0) {
      snprintf(err, errcap, "cannot open the button pipe %s: %s", spec + 5, strerror(errno));
      free(in);
      return PV_INPUT_ERR_OPEN;
    }
  } else {
    snprintf(err, errcap,
             "input '%s' not understood: use evdev:/dev/input/eventN, pipe:PATH or none", spec);
    free(in);
    return PV_INPUT_ERR_SPEC;
  }
  *out = in;
  return PV_INPUT_OK;
}

int pv_input_fd(const pv_input_t *in) { return in != NULL ? in->fd : -1; }

pv_input_status_t pv_input_read(pv_input_t *in, pv_key_t *keys, size_t cap, size_t *count,
                                char *err, size_t errcap) {
  if (count == NULL) return PV_INPUT_ERR_INVALID_ARGUMENT;
  *count = 0;
  if (in == NULL || in->kind == 0) return PV_INPUT_OK;
  return in->kind == 1 ? pv_input_read_evdev(in, keys, cap, count, err, errcap)
                       : pv_input_read_pipe(in, keys, cap, count);
}

void pv_input_close(pv_input_t *in) {
  if (in == NULL) return;
  if (in->fd >= 0) close(in->fd);
  free(in);
}
