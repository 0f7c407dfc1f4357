/*
 * The scanner's USB driver (libusb-1.0). Finds the scanner by vendor and
 * product id, claims its vendor interface, starts streaming with a vendor
 * control request, keeps several asynchronous bulk IN transfers in flight
 * and feeds their bytes to a pv_usb_stream (usb_stream.h), which hands the
 * checked points to the caller (the core session's push()).
 *
 * Device (protocol v1, docs/protocol/usb.md):
 *   vendor 0x1209 (pid.codes), product 0x7050 -- pitvol development id
 *   interface 0, class 0xFF (vendor), bulk IN endpoint 0x81
 *   control OUT, bmRequestType 0x41 (vendor | interface | host-to-device):
 *     bRequest 0x01 START (wValue 0, wIndex 0, no data): begin a scan,
 *                   sequence numbers restart at 0
 *     bRequest 0x02 STOP: end streaming (the device sends END_OF_SCAN)
 *
 * Unplug mid-scan: the partial scan is kept (the points already handed on
 * stay handed on), the state becomes PV_USB_STATE_UNPLUGGED, and poll()
 * waits for the device to come back (hotplug); on return the driver
 * re-claims it and resumes streaming. Timeouts and stalls are recovered
 * (clear halt, resubmit) or reported, never fatal. Fixed transfer buffers,
 * no allocation per frame.
 */
#ifndef PITVOL_USB_SCANNER_H
#define PITVOL_USB_SCANNER_H

#include <poll.h>
#include <stddef.h>
#include <stdint.h>

#include "pitvol/usb_stream.h"
#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_USB_VENDOR_ID 0x1209u
#define PV_USB_PRODUCT_ID 0x7050u
#define PV_USB_INTERFACE 0u
#define PV_USB_ENDPOINT_IN 0x81u
#define PV_USB_REQUEST_TYPE_OUT 0x41u
#define PV_USB_REQUEST_START 0x01u
#define PV_USB_REQUEST_STOP 0x02u
#define PV_USB_TRANSFERS 8u                 /* in flight */
#define PV_USB_TRANSFER_BYTES (64u * 1024u) /* each */
#define PV_USB_MAX_POLLFDS 16u              /* libusb descriptors tracked */

typedef enum pv_usb_status {
  /* 0, then 200 .. 299: PV_STATUS_BASE_USB (pitvol/status_codes.h) */
  PV_USB_OK = 0,
  PV_USB_ERR_INIT = 201,      /* libusb could not start */
  PV_USB_ERR_NOT_FOUND = 202, /* no scanner attached */
  PV_USB_ERR_ACCESS = 203,    /* permission denied: udev rule missing */
  PV_USB_ERR_BUSY = 204,      /* interface claimed by another program */
  PV_USB_ERR_IO = 205,        /* transfer failed and could not recover */
  PV_USB_ERR_STATE = 206      /* call not valid in this state */
} pv_usb_status_t;

typedef enum pv_usb_state {
  PV_USB_STATE_IDLE = 0,      /* open, not streaming */
  PV_USB_STATE_STREAMING = 1,
  PV_USB_STATE_ENDED = 2,     /* END_OF_SCAN received */
  PV_USB_STATE_UNPLUGGED = 3  /* device gone; waiting for it to return */
} pv_usb_state_t;

typedef struct pv_usb_scanner_stats {
  pv_usb_stream_stats_t stream;
  uint64_t transfers_completed;
  uint64_t transfers_short;   /* fewer bytes than asked (normal at scan end) */
  uint64_t stalls_cleared;
  uint64_t timeouts;
  uint64_t transfer_errors;
  uint64_t unplugs;
  uint64_t replugs;
} pv_usb_scanner_stats_t;

typedef struct pv_usb_scanner pv_usb_scanner_t;

/* on_points receives every accepted frame's good points. */
PV_NODISCARD pv_usb_status_t pv_usb_scanner_open(pv_usb_scanner_t **out, pv_usb_points_fn on_points,
                                                 void *user);
/* For the board application (firmware/): the scanner with these ids; if
 * wait_if_absent and no such scanner is attached, open succeeds anyway in
 * PV_USB_STATE_UNPLUGGED and poll() picks the scanner up when it arrives
 * (state IDLE). pv_usb_scanner_open() is this with the ids above and
 * wait_if_absent 0. */
PV_NODISCARD pv_usb_status_t pv_usb_scanner_open_ids(pv_usb_scanner_t **out, uint16_t vendor_id,
                                                     uint16_t product_id, int wait_if_absent,
                                                     pv_usb_points_fn on_points, void *user);
/* For a caller's own poll() loop (the board's event loop): copies up to cap
 * of the libusb descriptors to watch into fds and returns their count; sets
 * *timeout_ms to the longest the caller may sleep before calling
 * pv_usb_scanner_poll(s, 0) (-1: no limit; while unplugged, the period at
 * which the driver looks for the scanner). Does not allocate: the set is
 * kept up to date by libusb's pollfd notifiers. */
size_t pv_usb_scanner_pollfds(pv_usb_scanner_t *s, struct pollfd *fds, size_t cap,
                              int *timeout_ms);
PV_NODISCARD pv_usb_status_t pv_usb_scanner_start(pv_usb_scanner_t *s);
/* Handles USB events for up to timeout_ms; returns the state after. */
pv_usb_state_t pv_usb_scanner_poll(pv_usb_scanner_t *s, int timeout_ms);
PV_NODISCARD pv_usb_status_t pv_usb_scanner_stop(pv_usb_scanner_t *s);
void pv_usb_scanner_get_stats(const pv_usb_scanner_t *s, pv_usb_scanner_stats_t *out);
void pv_usb_scanner_close(pv_usb_scanner_t *s);
/* "PV_USB_ERR_ACCESS", ... and what went wrong and what to do. Never NULL. */
const char *pv_usb_status_name(pv_usb_status_t st);
const char *pv_usb_status_message(pv_usb_status_t st);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_USB_SCANNER_H */
