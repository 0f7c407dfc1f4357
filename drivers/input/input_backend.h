/* Internal: what each input backend provides to input.c. */
#ifndef PV_INPUT_BACKEND_H
#define PV_INPUT_BACKEND_H

#include "pitvol/input.h"

#define PV_PIPE_LINE_BYTES 64u

struct pv_input {
  int kind; /* 0 none, 1 evdev, 2 pipe */
  int fd;
  char line[PV_PIPE_LINE_BYTES]; /* pipe: the line being read */
  size_t line_len;
  int line_too_long;
};

pv_input_status_t pv_input_read_evdev(struct pv_input *in, pv_key_t *keys, size_t cap,
                                      size_t *count, char *err, size_t errcap);
pv_input_status_t pv_input_read_pipe(struct pv_input *in, pv_key_t *keys, size_t cap,
                                     size_t *count);
/* Maps an evdev key code to a button (PV_KEY_NONE if not a button). */
pv_key_t pv_input_evdev_key(unsigned code);

#endif
