/*
 * An emulated pitvol USB scanner (protocol v1, docs/protocol/usb.md) on
 * umockdev: a test bed with one USB device (1209:7050, vendor interface 0,
 * bulk IN 0x81, real `descriptors` blob) whose usbfs ioctls are answered by
 * this library, in the same process as the libusb code under test. The
 * process must run under `umockdev-wrapper` (LD_PRELOAD of
 * libumockdev-preload); create the emulator BEFORE libusb_init.
 *
 * It serves a byte stream of USB frames (a .frames file from `pitvol-sim
 * scan`, or memory). After the vendor request START each reaped bulk IN URB
 * gets up to its buffer length of the next bytes (frames split across URBs
 * and sharing them, exactly as on the wire); STOP ends the stream with an
 * empty END_OF_SCAN frame.
 *
 * Faults, all deterministic (seeded):
 *   corrupt_rate    share of frames whose CRC is flipped
 *   drop_rate       share of frames left out
 *   duplicate_rate  share of frames sent twice
 *                   (the last frame, END_OF_SCAN, is never corrupted or
 *                    dropped, so a scan always ends)
 *   stall_at_frame / stall_at_byte: the endpoint halts once there; URBs
 *                   fail with -EPIPE until the host sends CLEAR_HALT
 *   short_reads     URBs return a random 1..len bytes instead of len
 *   unplug_at_frame the device goes away half way through that frame:
 *                   pending URBs fail with -ENODEV, a "remove" uevent is
 *                   sent and the device is removed; it comes back after
 *                   replug_after_ms ("add" uevent, new device number), or
 *                   on pv_emu_replug() if replug_after_ms < 0. The next
 *                   START resumes at the start of the interrupted frame.
 *   pacing          bytes_per_interval every interval_ms (0: full speed)
 */
#ifndef PV_EMULATED_SCANNER_H
#define PV_EMULATED_SCANNER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pv_emu_options_s {
  uint32_t bytes_per_interval; /* 0: full speed */
  uint32_t interval_ms;
  double corrupt_rate;
  double drop_rate;
  double duplicate_rate;
  uint64_t seed;
  int64_t stall_at_frame;      /* -1: never */
  int64_t stall_at_byte;       /* -1: never */
  int short_reads;
  int64_t unplug_at_frame;     /* -1: never */
  int replug_after_ms;         /* < 0: only on pv_emu_replug() */
} pv_emu_options_t;

typedef struct pv_emu_stats_s {
  uint64_t frames_in;          /* frames in the source */
  uint64_t points_in;
  uint64_t frames_out;         /* frames in the served stream (after faults) */
  uint64_t bytes_out;          /* size of the served stream */
  uint64_t frames_corrupted;
  uint64_t frames_dropped;
  uint64_t points_dropped;     /* in dropped frames */
  uint64_t points_corrupted;   /* in corrupted frames */
  uint64_t frames_duplicated;
  uint64_t bytes_served;       /* bytes handed out in URBs (resends included) */
  uint64_t urbs_bulk;          /* bulk URBs completed with data */
  uint64_t urbs_stalled;       /* completed with -EPIPE */
  uint64_t urbs_nodev;         /* completed with -ENODEV */
  uint64_t urbs_discarded;
  uint64_t clear_halts;
  uint64_t starts;
  uint64_t stops;
  uint64_t unplugs;
  uint64_t replugs;
  int plugged;
  int finished;                /* the whole stream has been served */
} pv_emu_stats_t;

typedef struct pv_emu pv_emu_t;

void pv_emu_options_default(pv_emu_options_t *o);

/* 1 if this process runs under umockdev-wrapper (else nothing can work). */
int pv_emu_available(void);

/* Builds the test bed and plugs the scanner in. 0 on success, else -1 with
 * a message in err (errcap bytes). */
int pv_emu_create_from_file(pv_emu_t **out, const char *frames_path, const pv_emu_options_t *o,
                            char *err, size_t errcap);
int pv_emu_create_from_memory(pv_emu_t **out, const uint8_t *bytes, size_t len,
                              const pv_emu_options_t *o, char *err, size_t errcap);

/* The next scan: replaces the stream the device serves (the options stay),
 * as a scanner that stays plugged in measures pit after pit. Only between
 * scans (before the first START or after the stream ended); the next START
 * serves it from its first frame. 0 on success, else -1 with a message. */
int pv_emu_load_memory(pv_emu_t *e, const uint8_t *bytes, size_t len, char *err, size_t errcap);
int pv_emu_load_file(pv_emu_t *e, const char *frames_path, char *err, size_t errcap);

/* Unplug / replug now (whatever the options say). 0 on success. */
int pv_emu_unplug(pv_emu_t *e);
int pv_emu_replug(pv_emu_t *e);

void pv_emu_stats(pv_emu_t *e, pv_emu_stats_t *out);

/* Points in served frames [0, n) -- e.g. what reached the host before an
 * unplug at frame n. */
uint64_t pv_emu_points_before_frame(pv_emu_t *e, uint64_t n);
uint64_t pv_emu_frame_count(pv_emu_t *e);

void pv_emu_destroy(pv_emu_t *e);

#ifdef __cplusplus
}
#endif
#endif
