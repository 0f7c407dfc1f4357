/*
 * Reassembles USB frames (usb_frame.h) from the bulk byte stream and hands
 * their checked points on. Transport-free: the libusb driver feeds it
 * whatever each bulk transfer carried, in order; so can a test or a file.
 *
 * A frame may arrive split over several feeds, or share a feed with the
 * next. Every rejection is counted by reason; nothing is dropped silently:
 * - bytes that do not start a valid header are skipped until the next
 *   magic (resynchronisation), counted in bytes_skipped / headers_bad;
 * - a frame whose CRC fails is dropped whole (frames_bad_crc), and the
 *   search resumes one byte after its start, so a corrupt length cannot
 *   swallow the frames after it;
 * - points with NaN/Inf or |coordinate| > max_abs_mm are dropped
 *   (points_nonfinite, points_out_of_range), the rest of the frame is kept;
 * - sequence: a jump forward counts a gap and the frames lost; a sequence
 *   number already seen (equal or behind, within a window) is a duplicate
 *   and dropped; sequence 0 with no END_OF_SCAN before it starts a new scan.
 * Fixed memory (one frame buffer, one point buffer), no allocation.
 */
#ifndef PITVOL_USB_STREAM_H
#define PITVOL_USB_STREAM_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/pitvol.h"
#include "pitvol/usb_frame.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A sequence number up to this many frames behind the last accepted one
 * (or equal to it) is a duplicate; anything else not next is a jump forward
 * (modulo 2^32). Sequence 0 is the exception: it starts a new scan. */
#define PV_USB_STREAM_DUP_WINDOW 1024u

typedef struct pv_usb_stream_stats {
  uint64_t bytes_in;
  uint64_t bytes_skipped;       /* not part of any accepted frame header */
  uint64_t headers_bad;         /* resynchronisations started */
  uint64_t frames_ok;
  uint64_t frames_bad_crc;
  uint64_t frames_duplicate;
  uint64_t sequence_gaps;       /* jumps forward */
  uint64_t frames_lost;         /* sum of the jumps */
  uint64_t points_ok;
  uint64_t points_nonfinite;
  uint64_t points_out_of_range;
  uint64_t scans_ended;         /* END_OF_SCAN frames accepted */
} pv_usb_stream_stats_t;

/* Called once per accepted frame with its good points (n may be 0).
 * The points are valid only during the call. */
typedef void (*pv_usb_points_fn)(void *user, const pv_usb_frame_header_t *h,
                                 const pv_point_t *points, size_t n);

typedef struct pv_usb_stream {
  uint8_t frame[PV_USB_MAX_FRAME_BYTES]; /* bytes of the frame being built */
  size_t fill;
  pv_point_t points[PV_USB_MAX_POINTS];
  float max_abs_mm;
  int have_sequence;
  uint32_t last_sequence;
  pv_usb_points_fn on_points;
  void *user;
  pv_usb_stream_stats_t stats;
  /* Added with usb_stream.c (appended; the fields above are unchanged). */
  int resyncing;        /* searching for the next magic (bad header or CRC) */
  int last_end_of_scan; /* the last accepted frame carried END_OF_SCAN */
} pv_usb_stream_t;

void pv_usb_stream_init(pv_usb_stream_t *s, float max_abs_mm, pv_usb_points_fn on_points,
                        void *user);
/* Feeds the next len bytes of the stream. */
void pv_usb_stream_feed(pv_usb_stream_t *s, const uint8_t *data, size_t len);
/* Forgets a partial frame (after an unplug: the rest will never come) and
 * returns how many bytes were discarded; counted in bytes_skipped. */
size_t pv_usb_stream_drop_partial(pv_usb_stream_t *s);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_USB_STREAM_H */
