/* Input driver front (input.h): opens the backend named by the spec. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "input_backend.h"

const char *pv_key_name(pv_key_t k) {
  switch (k) {
    case PV_KEY_START_STOP: return "start/stop";
    case PV_KEY_ENTER: return "enter";
    case PV_KEY_BACK: return "back";
    case PV_KEY_NONE: break;
  }
  return "none";
}

int pv_input_open(pv_input_t **out, const char *spec, char *err, size_t errcap) {
  if (out == NULL || spec == NULL) {
    snprintf(err, errcap, "input: no spec given");
    return -1;
  }
  *out = NULL;
  struct pv_input *in = (struct pv_input *)calloc(1, sizeof *in);
  if (in == NULL) {
    snprintf(err, errcap, "input: out of memory");
    return -1;
  }
  in->fd = -1;
  if (strcmp(spec, "none") == 0) {
    *out = in;
    return 0;
  }
  if (strncmp(spec, "evdev:", 6) == 0) {
    in->kind = 1;
    in->fd = open(spec + 6, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (in->fd < 0) {
      snprintf(err, errcap, "cannot open buttons %s: %s (check the input config and permissions)",
               spec + 6, strerror(errno));
      free(in);
      return -1;
    }
  } else if (strncmp(spec, "pipe:", 5) == 0) {
    in->kind = 2;
    if (mkfifo(spec + 5, 0600) != 0 && errno != EEXIST) {
      snprintf(err, errcap, "cannot create the button pipe %s: %s", spec + 5, strerror(errno));
      free(in);
      return -1;
    }
    /* Read-write: we are a writer ourselves, so no EOF/POLLHUP when the
     * last outside writer closes. */
    in->fd = open(spec + 5, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (in->fd < 0) {
      snprintf(err, errcap, "cannot open the button pipe %s: %s", spec + 5, strerror(errno));
      free(in);
      return -1;
    }
  } else {
    snprintf(err, errcap,
             "input '%s' not understood: use evdev:/dev/input/eventN, pipe:PATH or none", spec);
    free(in);
    return -1;
  }
  *out = in;
  return 0;
}

int pv_input_fd(const pv_input_t *in) { return in != NULL ? in->fd : -1; }

int pv_input_read(pv_input_t *in, pv_key_t *keys, size_t cap, char *err, size_t errcap) {
  if (in == NULL || in->kind == 0) return 0;
  return in->kind == 1 ? pv_input_read_evdev(in, keys, cap, err, errcap)
                       : pv_input_read_pipe(in, keys, cap, err, errcap);
}

void pv_input_close(pv_input_t *in) {
  if (in == NULL) return;
  if (in->fd >= 0) close(in->fd);
  free(in);
}
