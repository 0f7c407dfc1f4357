/*
 * evdev backend: struct input_event records from /dev/input/eventN
 * (gpio-keys on the board). Only EV_KEY presses count; releases (0) and
 * autorepeat (2) do not, so holding a button does not start and stop a
 * scan in turn.
 */
#include <errno.h>
#include <linux/input.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "input_backend.h"

pv_key_t pv_input_evdev_key(unsigned code) {
  switch (code) {
    case KEY_RECORD:
    case KEY_PLAYPAUSE:
    case KEY_SPACE:
    case KEY_S: return PV_KEY_START_STOP;
    case KEY_ENTER:
    case KEY_OK:
    case KEY_SELECT:
    case KEY_KPENTER: return PV_KEY_ENTER;
    case KEY_BACK:
    case KEY_ESC:
    case KEY_BACKSPACE:
    case KEY_B: return PV_KEY_BACK;
    default: return PV_KEY_NONE;
  }
}

pv_input_status_t pv_input_read_evdev(struct pv_input *in, pv_key_t *keys, size_t cap,
                                      size_t *count, char *err, size_t errcap) {
  size_t n = 0;
  *count = 0;
  struct input_event ev[16];
  while (n < cap) {
    const ssize_t r = read(in->fd, ev, sizeof ev);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    if (r <= 0) {
      snprintf(err, errcap, "the buttons' input device went away (%s)",
               r == 0 ? "end of file" : strerror(errno));
      *count = n;
      return PV_INPUT_ERR_GONE;
    }
    const size_t events = (size_t)r / sizeof ev[0];
    for (size_t i = 0; i < events && n < cap; ++i) {
      if (ev[i].type != EV_KEY || ev[i].value != 1) continue;
      const pv_key_t k = pv_input_evdev_key(ev[i].code);
      if (k != PV_KEY_NONE) keys[n++] = k;
    }
    if ((size_t)r < sizeof ev) break;
  }
  *count = n;
  return PV_INPUT_OK;
}
