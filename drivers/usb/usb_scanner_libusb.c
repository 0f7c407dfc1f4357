/*
 * The scanner's USB driver on libusb-1.0 (contract: usb_scanner.h).
 *
 * One libusb context per scanner. PV_USB_TRANSFERS bulk IN transfers of
 * PV_USB_TRANSFER_BYTES each are allocated once at open (one buffer block)
 * and stay in flight while streaming; every completion feeds its bytes, in
 * completion order, to the pv_usb_stream and is resubmitted. Nothing is
 * allocated per frame or per transfer.
 *
 * Recovery:
 *   STALL      -> libusb_clear_halt + resubmit       (stalls_cleared)
 *   TIMED_OUT  -> feed what arrived + resubmit       (timeouts)
 *   ERROR      -> resubmit; if that says the device is gone, as NO_DEVICE
 *   NO_DEVICE  -> state UNPLUGGED, partial frame dropped, the handle closed
 *                 once every transfer is back; poll() then waits for the
 *                 scanner (hotplug callback, or re-enumeration every
 *                 PV_USB_RESCAN_MS without hotplug support), re-opens,
 *                 re-claims, sends START again and resubmits (replugs).
 * END_OF_SCAN accepted by the stream (scans_ended grows) -> state ENDED.
 *
 * Threading: single-threaded; every callback runs inside poll() (or inside
 * start/stop/close, which run the event loop too).
 */
#include "pitvol/usb_scanner.h"

#include <libusb.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

_Static_assert(PV_USB_ERR_INIT > PV_STATUS_BASE_USB &&
                   PV_USB_ERR_STATE < PV_STATUS_BASE_USB + PV_STATUS_RANGE,
               "pv_usb_status_t in its range (pitvol/status_codes.h)");

#define PV_USB_TIMEOUT_MS 1000u      /* per bulk transfer */
#define PV_USB_CONTROL_TIMEOUT_MS 1000u
#define PV_USB_RESCAN_MS 100u        /* re-enumeration period without hotplug */
#define PV_USB_HOTPLUG_RESCAN_MS 500u /* safety re-enumeration with hotplug */
#define PV_USB_MAX_ABS_MM 1.0e6f     /* the core's "absurd" limit */

struct pv_usb_scanner {
  libusb_context *ctx;
  libusb_device_handle *handle;
  struct libusb_transfer *xfer[PV_USB_TRANSFERS];
  uint8_t *buffers; /* PV_USB_TRANSFERS * PV_USB_TRANSFER_BYTES */
  unsigned inflight;
  uint8_t busy[PV_USB_TRANSFERS]; /* submitted, not yet completed */
  pv_usb_state_t state;
  int want_streaming; /* START was asked for and not STOPped */
  int closing;
  int has_hotplug;
  libusb_hotplug_callback_handle hotplug;
  int arrived;        /* hotplug: a matching device arrived */
  int left;           /* hotplug: our device left (noticed with nothing in flight) */
  uint64_t last_scan_ms;
  uint64_t scans_ended_seen;
  pv_usb_points_fn on_points;
  void *user;
  pv_usb_scanner_stats_t stats;
  uint16_t vendor_id, product_id;
  struct pollfd pollfds[PV_USB_MAX_POLLFDS]; /* libusb's, via its notifiers */
  size_t npollfds;
  pv_usb_stream_t stream; /* large: last */
};

static void cancel_all(pv_usb_scanner_t *s);

static uint64_t now_ms(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

const char *pv_usb_status_name(pv_usb_status_t st) {
  switch (st) {
    case PV_USB_OK: return "PV_USB_OK";
    case PV_USB_ERR_INIT: return "PV_USB_ERR_INIT";
    case PV_USB_ERR_NOT_FOUND: return "PV_USB_ERR_NOT_FOUND";
    case PV_USB_ERR_ACCESS: return "PV_USB_ERR_ACCESS";
    case PV_USB_ERR_BUSY: return "PV_USB_ERR_BUSY";
    case PV_USB_ERR_IO: return "PV_USB_ERR_IO";
    case PV_USB_ERR_STATE: return "PV_USB_ERR_STATE";
  }
  return "PV_USB_ERR_UNKNOWN";
}

const char *pv_usb_status_message(pv_usb_status_t st) {
  switch (st) {
    case PV_USB_OK: return "ok";
    case PV_USB_ERR_INIT: return "libusb could not be initialised";
    case PV_USB_ERR_NOT_FOUND: return "no pitvol scanner (1209:7050) is attached";
    case PV_USB_ERR_ACCESS:
      return "permission denied opening the scanner: install the udev rule or run with access to /dev/bus/usb";
    case PV_USB_ERR_BUSY: return "the scanner's interface is claimed by another program";
    case PV_USB_ERR_IO: return "a USB transfer failed and could not be recovered";
    case PV_USB_ERR_STATE: return "the call is not valid in the scanner's current state";
  }
  return "unknown status";
}

static pv_usb_status_t map_error(int r) {
  switch (r) {
    case LIBUSB_SUCCESS: return PV_USB_OK;
    case LIBUSB_ERROR_ACCESS: return PV_USB_ERR_ACCESS;
    case LIBUSB_ERROR_BUSY: return PV_USB_ERR_BUSY;
    case LIBUSB_ERROR_NO_DEVICE:
    case LIBUSB_ERROR_NOT_FOUND: return PV_USB_ERR_NOT_FOUND;
    default: return PV_USB_ERR_IO;
  }
}

/* ---- device gone / back --------------------------------------------- */

static void device_gone(pv_usb_scanner_t *s) {
  if (s->state == PV_USB_STATE_UNPLUGGED) return;
  s->state = PV_USB_STATE_UNPLUGGED;
  s->stats.unplugs++;
  s->arrived = 0;
  s->last_scan_ms = now_ms();
  (void)pv_usb_stream_drop_partial(&s->stream);
  /* The other transfers come back with NO_DEVICE on their own; cancelling
   * them too makes sure they do even if the OS keeps them queued. */
  cancel_all(s);
}

/* Closes the old handle once no transfer refers to it any more. */
static void reap_old_handle(pv_usb_scanner_t *s) {
  if (s->state != PV_USB_STATE_UNPLUGGED || s->handle == NULL || s->inflight != 0) return;
  (void)libusb_release_interface(s->handle, (int)PV_USB_INTERFACE);
  libusb_close(s->handle);
  s->handle = NULL;
}

static void note_stream_progress(pv_usb_scanner_t *s) {
  if (s->stream.stats.scans_ended != s->scans_ended_seen) {
    s->scans_ended_seen = s->stream.stats.scans_ended;
    if (s->state == PV_USB_STATE_STREAMING) s->state = PV_USB_STATE_ENDED;
  }
}

static int xfer_index(const pv_usb_scanner_t *s, const struct libusb_transfer *t) {
  for (unsigned i = 0; i < PV_USB_TRANSFERS; ++i) {
    if (s->xfer[i] == t) return (int)i;
  }
  return -1;
}

static int submit(pv_usb_scanner_t *s, struct libusb_transfer *t) {
  const int r = libusb_submit_transfer(t);
  if (r == LIBUSB_SUCCESS) {
    s->inflight++;
    s->busy[xfer_index(s, t)] = 1;
  } else if (r == LIBUSB_ERROR_NO_DEVICE) {
    device_gone(s);
  } else {
    s->stats.transfer_errors++;
  }
  return r;
}

static void cancel_all(pv_usb_scanner_t *s) {
  for (unsigned i = 0; i < PV_USB_TRANSFERS; ++i) {
    if (s->xfer[i] != NULL && s->busy[i]) (void)libusb_cancel_transfer(s->xfer[i]);
  }
}

static void LIBUSB_CALL transfer_done(struct libusb_transfer *t) {
  pv_usb_scanner_t *s = (pv_usb_scanner_t *)t->user_data;
  s->inflight--;
  s->busy[xfer_index(s, t)] = 0;
  if (t->actual_length > 0 && s->state != PV_USB_STATE_UNPLUGGED) {
    const pv_usb_state_t before = s->state;
    pv_usb_stream_feed(&s->stream, t->buffer, (size_t)t->actual_length);
    note_stream_progress(s);
    /* Scan over: the other transfers are not needed until the next START. */
    if (before == PV_USB_STATE_STREAMING && s->state == PV_USB_STATE_ENDED) cancel_all(s);
  }
  switch (t->status) {
    case LIBUSB_TRANSFER_COMPLETED:
      s->stats.transfers_completed++;
      if (t->actual_length < t->length) s->stats.transfers_short++;
      break;
    case LIBUSB_TRANSFER_TIMED_OUT:
      s->stats.timeouts++;
      break;
    case LIBUSB_TRANSFER_STALL:
      if (!s->closing && s->state != PV_USB_STATE_UNPLUGGED) {
        const int r = libusb_clear_halt(t->dev_handle, (unsigned char)PV_USB_ENDPOINT_IN);
        if (r == LIBUSB_SUCCESS) {
          s->stats.stalls_cleared++;
        } else if (r == LIBUSB_ERROR_NO_DEVICE) {
          device_gone(s);
        } else {
          s->stats.transfer_errors++;
        }
      }
      break;
    case LIBUSB_TRANSFER_NO_DEVICE:
      device_gone(s);
      break;
    case LIBUSB_TRANSFER_CANCELLED:
      /* Ours (close, end of scan, unplug); resubmitted below if streaming
       * again by now. libusb reports its own timeout cancels as TIMED_OUT. */
      break;
    case LIBUSB_TRANSFER_ERROR:
    case LIBUSB_TRANSFER_OVERFLOW:
    default:
      s->stats.transfer_errors++;
      break;
  }
  if (!s->closing && s->state == PV_USB_STATE_STREAMING) (void)submit(s, t);
}

static int LIBUSB_CALL hotplug_cb(libusb_context *ctx, libusb_device *dev,
                                  libusb_hotplug_event event, void *user) {
  (void)ctx;
  pv_usb_scanner_t *s = (pv_usb_scanner_t *)user;
  if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED) s->arrived = 1;
  /* Without transfers in flight (IDLE, ENDED) nothing else would notice. */
  if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT && s->handle != NULL &&
      libusb_get_device(s->handle) == dev) {
    s->left = 1;
  }
  return 0; /* stay registered */
}

/* Finds and opens the scanner, detaches a kernel driver, claims interface 0. */
static pv_usb_status_t open_device(pv_usb_scanner_t *s) {
  libusb_device **list = NULL;
  const ssize_t n = libusb_get_device_list(s->ctx, &list);
  if (n < 0) return PV_USB_ERR_IO;
  int r = LIBUSB_ERROR_NOT_FOUND;
  libusb_device_handle *h = NULL;
  for (ssize_t i = 0; i < n; ++i) {
    struct libusb_device_descriptor d;
    if (libusb_get_device_descriptor(list[i], &d) != LIBUSB_SUCCESS) continue;
    if (d.idVendor != s->vendor_id || d.idProduct != s->product_id) continue;
    r = libusb_open(list[i], &h);
    if (r == LIBUSB_SUCCESS) break;
  }
  libusb_free_device_list(list, 1);
  if (r != LIBUSB_SUCCESS) return map_error(r);
  if (libusb_kernel_driver_active(h, (int)PV_USB_INTERFACE) == 1) {
    (void)libusb_detach_kernel_driver(h, (int)PV_USB_INTERFACE);
  }
  r = libusb_claim_interface(h, (int)PV_USB_INTERFACE);
  if (r != LIBUSB_SUCCESS) {
    libusb_close(h);
    return map_error(r);
  }
  s->handle = h;
  for (unsigned i = 0; i < PV_USB_TRANSFERS; ++i) {
    libusb_fill_bulk_transfer(s->xfer[i], h, (unsigned char)PV_USB_ENDPOINT_IN,
                              s->buffers + (size_t)i * PV_USB_TRANSFER_BYTES,
                              (int)PV_USB_TRANSFER_BYTES, transfer_done, s, PV_USB_TIMEOUT_MS);
  }
  return PV_USB_OK;
}

static pv_usb_status_t send_request(pv_usb_scanner_t *s, uint8_t request) {
  const int r = libusb_control_transfer(s->handle, (uint8_t)PV_USB_REQUEST_TYPE_OUT, request, 0,
                                        0, NULL, 0, PV_USB_CONTROL_TIMEOUT_MS);
  if (r == LIBUSB_ERROR_NO_DEVICE) device_gone(s);
  return r < 0 ? map_error(r) : PV_USB_OK;
}

/* START, then every transfer that is not already in flight. */
static pv_usb_status_t begin_streaming(pv_usb_scanner_t *s) {
  pv_usb_status_t st = send_request(s, (uint8_t)PV_USB_REQUEST_START);
  if (st != PV_USB_OK) return st;
  s->state = PV_USB_STATE_STREAMING;
  /* Transfers still coming back (cancelled at the end of the last scan)
   * are resubmitted by their callback. */
  for (unsigned i = 0; i < PV_USB_TRANSFERS; ++i) {
    if (s->busy[i]) continue;
    const int r = submit(s, s->xfer[i]);
    if (r == LIBUSB_ERROR_NO_DEVICE) return PV_USB_ERR_NOT_FOUND;
    if (r != LIBUSB_SUCCESS) return map_error(r);
  }
  return PV_USB_OK;
}

/* While unplugged: look for the scanner again and resume. */
static void try_replug(pv_usb_scanner_t *s) {
  if (s->state != PV_USB_STATE_UNPLUGGED || s->handle != NULL || s->closing) return;
  const uint64_t t = now_ms();
  const uint64_t period = s->has_hotplug ? PV_USB_HOTPLUG_RESCAN_MS : PV_USB_RESCAN_MS;
  if (!s->arrived && t - s->last_scan_ms < period) return;
  s->arrived = 0;
  s->last_scan_ms = t;
  if (open_device(s) != PV_USB_OK) return;
  if (!s->want_streaming) {
    s->stats.replugs++;
    s->state = PV_USB_STATE_IDLE;
    return;
  }
  if (begin_streaming(s) == PV_USB_OK) {
    s->stats.replugs++;
  } else if (s->state != PV_USB_STATE_UNPLUGGED) {
    /* START failed on a device that is there: close it, retry later. */
    s->state = PV_USB_STATE_UNPLUGGED;
    cancel_all(s);
  }
}

/* Runs libusb's event loop for at most ms milliseconds. */
static void handle_events(pv_usb_scanner_t *s, int ms) {
  struct timeval tv;
  if (ms < 0) ms = 0;
  tv.tv_sec = ms / 1000;
  tv.tv_usec = (ms % 1000) * 1000;
  (void)libusb_handle_events_timeout_completed(s->ctx, &tv, NULL);
}

/* ---- descriptors for a caller's poll() --------------------------------- */

static void LIBUSB_CALL pollfd_added(int fd, short events, void *user) {
  pv_usb_scanner_t *s = (pv_usb_scanner_t *)user;
  for (size_t i = 0; i < s->npollfds; ++i) {
    if (s->pollfds[i].fd == fd) {
      s->pollfds[i].events = events;
      return;
    }
  }
  if (s->npollfds < PV_USB_MAX_POLLFDS) {
    s->pollfds[s->npollfds].fd = fd;
    s->pollfds[s->npollfds].events = events;
    s->pollfds[s->npollfds].revents = 0;
    s->npollfds++;
  }
}

static void LIBUSB_CALL pollfd_removed(int fd, void *user) {
  pv_usb_scanner_t *s = (pv_usb_scanner_t *)user;
  for (size_t i = 0; i < s->npollfds; ++i) {
    if (s->pollfds[i].fd == fd) {
      s->pollfds[i] = s->pollfds[--s->npollfds];
      return;
    }
  }
}

/* The descriptors libusb has now (once, at open), then the notifiers. */
static void track_pollfds(pv_usb_scanner_t *s) {
  const struct libusb_pollfd **list = libusb_get_pollfds(s->ctx);
  if (list != NULL) {
    for (size_t i = 0; list[i] != NULL; ++i) pollfd_added(list[i]->fd, list[i]->events, s);
    libusb_free_pollfds(list);
  }
  libusb_set_pollfd_notifiers(s->ctx, pollfd_added, pollfd_removed, s);
}

size_t pv_usb_scanner_pollfds(pv_usb_scanner_t *s, struct pollfd *fds, size_t cap,
                              int *timeout_ms) {
  if (timeout_ms != NULL) *timeout_ms = -1;
  if (s == NULL) return 0;
  size_t n = 0;
  for (size_t i = 0; i < s->npollfds && n < cap; ++i) {
    /* A device descriptor (usbfs: POLLOUT = URB to reap) with no transfer
     * in flight has nothing to say; leaving it out keeps an idle caller
     * asleep where the node always polls ready (umockdev). */
    if ((s->pollfds[i].events & POLLOUT) && s->inflight == 0) continue;
    fds[n] = s->pollfds[i];
    fds[n].revents = 0;
    ++n;
  }
  if (timeout_ms != NULL) {
    struct timeval tv;
    if (libusb_get_next_timeout(s->ctx, &tv) == 1) {
      *timeout_ms = (int)(tv.tv_sec * 1000 + (tv.tv_usec + 999) / 1000);
    }
    if (s->state == PV_USB_STATE_UNPLUGGED) {
      const int period = (int)(s->has_hotplug ? PV_USB_HOTPLUG_RESCAN_MS : PV_USB_RESCAN_MS);
      if (*timeout_ms < 0 || *timeout_ms > period) *timeout_ms = period;
    }
  }
  return n;
}

/* ---- public API ------------------------------------------------------ */

pv_usb_status_t pv_usb_scanner_open(pv_usb_scanner_t **out, pv_usb_points_fn on_points,
                                    void *user) {
  return pv_usb_scanner_open_ids(out, (uint16_t)PV_USB_VENDOR_ID, (uint16_t)PV_USB_PRODUCT_ID, 0,
                                 on_points, user);
}

pv_usb_status_t pv_usb_scanner_open_ids(pv_usb_scanner_t **out, uint16_t vendor_id,
                                        uint16_t product_id, int wait_if_absent,
                                        pv_usb_points_fn on_points, void *user) {
  if (out == NULL) return PV_USB_ERR_STATE;
  *out = NULL;
  pv_usb_scanner_t *s = (pv_usb_scanner_t *)calloc(1, sizeof *s);
  if (s == NULL) return PV_USB_ERR_INIT;
  s->on_points = on_points;
  s->user = user;
  s->vendor_id = vendor_id;
  s->product_id = product_id;
  pv_usb_stream_init(&s->stream, PV_USB_MAX_ABS_MM, on_points, user);
  if (libusb_init(&s->ctx) != LIBUSB_SUCCESS) {
    free(s);
    return PV_USB_ERR_INIT;
  }
  s->buffers = (uint8_t *)malloc((size_t)PV_USB_TRANSFERS * PV_USB_TRANSFER_BYTES);
  int ok = s->buffers != NULL;
  for (unsigned i = 0; ok && i < PV_USB_TRANSFERS; ++i) {
    s->xfer[i] = libusb_alloc_transfer(0);
    ok = s->xfer[i] != NULL;
  }
  if (!ok) {
    pv_usb_scanner_close(s);
    return PV_USB_ERR_INIT;
  }
  const pv_usb_status_t st = open_device(s);
  const int absent = st == PV_USB_ERR_NOT_FOUND && wait_if_absent;
  if (st != PV_USB_OK && !absent) {
    pv_usb_scanner_close(s);
    return st;
  }
  if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
    s->has_hotplug = libusb_hotplug_register_callback(
                         s->ctx,
                         (libusb_hotplug_event)(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                                LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
                         LIBUSB_HOTPLUG_NO_FLAGS,
                         (int)vendor_id, (int)product_id, LIBUSB_HOTPLUG_MATCH_ANY,
                         hotplug_cb, s, &s->hotplug) == LIBUSB_SUCCESS;
  }
  track_pollfds(s);
  /* Absent: exactly the state after an unplug with nothing to resume. */
  s->state = absent ? PV_USB_STATE_UNPLUGGED : PV_USB_STATE_IDLE;
  s->last_scan_ms = now_ms();
  *out = s;
  return PV_USB_OK;
}

pv_usb_status_t pv_usb_scanner_start(pv_usb_scanner_t *s) {
  if (s == NULL || s->handle == NULL) return PV_USB_ERR_STATE;
  if (s->state != PV_USB_STATE_IDLE && s->state != PV_USB_STATE_ENDED) return PV_USB_ERR_STATE;
  s->want_streaming = 1;
  return begin_streaming(s);
}

pv_usb_state_t pv_usb_scanner_poll(pv_usb_scanner_t *s, int timeout_ms) {
  if (s == NULL) return PV_USB_STATE_UNPLUGGED;
  const pv_usb_state_t before = s->state;
  const uint64_t deadline = now_ms() + (uint64_t)(timeout_ms > 0 ? timeout_ms : 0);
  for (;;) {
    if (s->left) {
      s->left = 0;
      device_gone(s);
    }
    reap_old_handle(s);
    try_replug(s);
    if (s->state != before) break;
    const uint64_t t = now_ms();
    if (t >= deadline) {
      if (timeout_ms <= 0) handle_events(s, 0);
      break;
    }
    int slice = (int)(deadline - t);
    /* While unplugged, come back often enough to look for the device. */
    if (s->state == PV_USB_STATE_UNPLUGGED && slice > 20) slice = 20;
    handle_events(s, slice);
    if (s->state != before) break;
  }
  if (s->left) { /* a hotplug LEFT seen in the last handle_events() */
    s->left = 0;
    device_gone(s);
  }
  reap_old_handle(s);
  return s->state;
}

pv_usb_status_t pv_usb_scanner_stop(pv_usb_scanner_t *s) {
  if (s == NULL) return PV_USB_ERR_STATE;
  s->want_streaming = 0;
  if (s->state != PV_USB_STATE_STREAMING) return PV_USB_OK;
  const pv_usb_status_t st = send_request(s, (uint8_t)PV_USB_REQUEST_STOP);
  if (st != PV_USB_OK) return st;
  /* The device answers with END_OF_SCAN: wait a little for it. */
  const uint64_t deadline = now_ms() + PV_USB_CONTROL_TIMEOUT_MS;
  while (s->state == PV_USB_STATE_STREAMING && now_ms() < deadline) handle_events(s, 10);
  return PV_USB_OK;
}

void pv_usb_scanner_get_stats(const pv_usb_scanner_t *s, pv_usb_scanner_stats_t *out) {
  if (out == NULL) return;
  if (s == NULL) {
    memset(out, 0, sizeof *out);
    return;
  }
  *out = s->stats;
  out->stream = s->stream.stats;
}

void pv_usb_scanner_close(pv_usb_scanner_t *s) {
  if (s == NULL) return;
  s->closing = 1;
  if (s->ctx != NULL) {
    cancel_all(s);
    const uint64_t deadline = now_ms() + 2000u;
    while (s->inflight > 0 && now_ms() < deadline) handle_events(s, 10);
    if (s->has_hotplug) libusb_hotplug_deregister_callback(s->ctx, s->hotplug);
    if (s->handle != NULL) {
      (void)libusb_release_interface(s->handle, (int)PV_USB_INTERFACE);
      libusb_close(s->handle);
      s->handle = NULL;
    }
  }
  /* A transfer still in flight after the deadline must not be freed. */
  if (s->inflight == 0) {
    for (unsigned i = 0; i < PV_USB_TRANSFERS; ++i) libusb_free_transfer(s->xfer[i]);
    free(s->buffers);
  }
  if (s->ctx != NULL && s->inflight == 0) libusb_exit(s->ctx);
  if (s->inflight == 0) free(s);
}
