/*
 * Which part of the board application is running, for the allocation
 * counter of the host build (firmware/host/alloc_counter.c): the board's
 * own code and the core's push() must never allocate once the loop runs;
 * libusb (per-URB bookkeeping) and the core's estimate/finish (the kd-tree
 * scratch of docs/memory.md) are counted apart and reported. Thread-local:
 * helper threads (libusb's hotplug monitor, the emulator) are not counted.
 * On the board the variable is set and never read.
 */
#ifndef PV_BOARD_ALLOC_ZONE_H
#define PV_BOARD_ALLOC_ZONE_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pv_alloc_zone {
  PV_ZONE_NONE = 0,    /* start-up, shutdown, other threads: not counted */
  PV_ZONE_BOARD = 1,   /* the event loop, state machine, screens, drivers */
  PV_ZONE_PUSH = 2,    /* pv_session_push from the USB callback */
  PV_ZONE_USB = 3,     /* inside libusb (pv_usb_scanner_*) */
  PV_ZONE_MEASURE = 4, /* pv_session_estimate / finish */
  PV_ZONE_COUNT = 5
} pv_alloc_zone_t;

extern _Thread_local int pv_alloc_zone;

static inline int pv_alloc_zone_enter(int zone) {
  const int old = pv_alloc_zone;
  pv_alloc_zone = zone;
  return old;
}

#ifdef __cplusplus
}
#endif
#endif
