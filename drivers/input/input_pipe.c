/*
 * Named-pipe backend for host runs: one word per line (start, stop, enter,
 * back). Partial lines wait for their newline; an overlong line is dropped
 * whole.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "input_backend.h"

static pv_key_t word_key(const char *w) {
  if (strcmp(w, "start") == 0 || strcmp(w, "stop") == 0) return PV_KEY_START_STOP;
  if (strcmp(w, "enter") == 0) return PV_KEY_ENTER;
  if (strcmp(w, "back") == 0) return PV_KEY_BACK;
  return PV_KEY_NONE;
}

/* Never fails: we hold a writer ourselves, so the pipe cannot go away. */
pv_input_status_t pv_input_read_pipe(struct pv_input *in, pv_key_t *keys, size_t cap,
                                     size_t *count) {
  size_t n = 0;
  char buf[128];
  for (;;) {
    const ssize_t r = read(in->fd, buf, sizeof buf);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break; /* EAGAIN: nothing more; 0 cannot happen (we hold a writer) */
    for (ssize_t i = 0; i < r; ++i) {
      const char ch = buf[i];
      if (ch == '\n') {
        in->line[in->line_len] = '\0';
        /* trim a trailing CR and spaces */
        while (in->line_len > 0 && (in->line[in->line_len - 1] == '\r' || in->line[in->line_len - 1] == ' ')) {
          in->line[--in->line_len] = '\0';
        }
        const pv_key_t k = in->line_too_long ? PV_KEY_NONE : word_key(in->line);
        if (k != PV_KEY_NONE && n < cap) {
          keys[n++] = k;
        } else if (k != PV_KEY_NONE) {
          fprintf(stderr, "pitvol input: more than %zu presses at once; '%s' dropped\n", cap,
                  in->line);
        } else if (in->line_len > 0 || in->line_too_long) {
          fprintf(stderr, "pitvol input: ignored pipe line '%s' (start, stop, enter or back)\n",
                  in->line_too_long ? "(too long)" : in->line);
        }
        in->line_len = 0;
        in->line_too_long = 0;
      } else if (in->line_len + 1 < sizeof in->line) {
        in->line[in->line_len++] = ch;
      } else {
        in->line_too_long = 1;
      }
    }
  }
  *count = n;
  return PV_INPUT_OK;
}
