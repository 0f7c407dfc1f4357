/* Frame stream reassembler (see usb_stream.h).
 *
 * The unconsumed stream is, logically, the bytes buffered in s->frame
 * (s->fill of them: the start of a frame that straddled feeds) followed by
 * the caller's data. step() makes one decision at the front of that stream
 * and says how many bytes it consumed, or that it needs more. Whole frames
 * inside one feed are checked and decoded in place from the caller's data;
 * only a frame (or header, or magic prefix) cut by the end of a feed is
 * copied into s->frame, at most PV_USB_MAX_FRAME_BYTES.
 *
 * Accounting: every byte fed ends up in exactly one of bytes_skipped, an
 * accepted or duplicate frame, or s->fill (pending):
 *   bytes_in == bytes_skipped + bytes of (frames_ok + frames_duplicate) + fill.
 *
 * Resynchronisation: where a header is expected and the bytes there are not
 * a valid header, one resync episode starts (headers_bad + 1) and the
 * search for the next magic begins one byte later. The episode ends at the
 * next full magic; if the header there is bad too, a new episode starts.
 * A complete frame whose CRC fails counts frames_bad_crc only, and the
 * search resumes at its second byte (no headers_bad for that search).
 */
#include "pitvol/usb_stream.h"

#include <float.h>
#include <string.h>

static const uint8_t kMagic[4] = {(uint8_t)(PV_USB_FRAME_MAGIC & 0xffu),
                                  (uint8_t)((PV_USB_FRAME_MAGIC >> 8) & 0xffu),
                                  (uint8_t)((PV_USB_FRAME_MAGIC >> 16) & 0xffu),
                                  (uint8_t)((PV_USB_FRAME_MAGIC >> 24) & 0xffu)};

static size_t min_size(size_t a, size_t b) { return a < b ? a : b; }

/* First position i in p[0..n) where the magic starts, or where a proper
 * prefix of it runs to the end of p; n if there is none. */
static size_t find_magic(const uint8_t *p, size_t n) {
  size_t i = 0;
  while (i < n) {
    const uint8_t *q = (const uint8_t *)memchr(p + i, kMagic[0], n - i);
    if (q == NULL) return n;
    i = (size_t)(q - p);
    if (memcmp(q, kMagic, min_size(n - i, sizeof kMagic)) == 0) return i;
    ++i;
  }
  return n;
}

static int is_finite_f32(float f) {
  uint32_t v;
  memcpy(&v, &f, sizeof v);
  return (v & 0x7f800000u) != 0x7f800000u; /* exponent all ones: Inf or NaN */
}

/* Sequence bookkeeping for a frame with a good CRC. 1 if it is to be
 * delivered, 0 if it is a duplicate (counted). */
static int sequence_accept(pv_usb_stream_t *s, const pv_usb_frame_header_t *h) {
  const uint32_t seq = h->sequence;
  if (s->have_sequence) {
    const uint32_t last = s->last_sequence;
    if (s->last_end_of_scan) {
      /* The next scan starts at 0; a repeat of the END_OF_SCAN frame is a
       * duplicate; any other number is the new scan with its first frames
       * lost. */
      if (seq == last) {
        s->stats.frames_duplicate++;
        return 0;
      }
      if (seq != 0) {
        s->stats.sequence_gaps++;
        s->stats.frames_lost += seq;
      }
    } else if (seq != last + 1u) {
      if (seq == last) {
        s->stats.frames_duplicate++;
        return 0;
      }
      if (seq != 0) { /* 0 without END_OF_SCAN before it: a new scan */
        if (last - seq < PV_USB_STREAM_DUP_WINDOW) {
          s->stats.frames_duplicate++;
          return 0;
        }
        s->stats.sequence_gaps++;
        s->stats.frames_lost += (uint32_t)(seq - last - 1u);
      }
    }
  }
  s->have_sequence = 1;
  s->last_sequence = seq;
  s->last_end_of_scan = (h->flags & PV_USB_FLAG_END_OF_SCAN) != 0;
  return 1;
}

/* A complete frame at p with a good CRC. */
static void accept_frame(pv_usb_stream_t *s, const uint8_t *p, const pv_usb_frame_header_t *h) {
  if (!sequence_accept(s, h)) return;
  s->stats.frames_ok++;
  if (h->flags & PV_USB_FLAG_END_OF_SCAN) s->stats.scans_ended++;
  const float lim = s->max_abs_mm;
  size_t n = 0;
  for (uint16_t i = 0; i < h->point_count; ++i) {
    float xyz[3];
    pv_usb_frame_point(p, i, xyz);
    if (!is_finite_f32(xyz[0]) || !is_finite_f32(xyz[1]) || !is_finite_f32(xyz[2])) {
      s->stats.points_nonfinite++;
      continue;
    }
    if (xyz[0] > lim || xyz[0] < -lim || xyz[1] > lim || xyz[1] < -lim || xyz[2] > lim ||
        xyz[2] < -lim) {
      s->stats.points_out_of_range++;
      continue;
    }
    s->points[n].x_mm = xyz[0];
    s->points[n].y_mm = xyz[1];
    s->points[n].z_mm = xyz[2];
    ++n;
  }
  s->stats.points_ok += n;
  if (s->on_points != NULL) s->on_points(s->user, h, s->points, n);
}

/* One decision at the front of the unconsumed stream, p[0..n), n >= 1.
 * Returns the bytes consumed (> 0), or 0 if the decision needs the first
 * *need bytes (*need > n). */
static size_t step(pv_usb_stream_t *s, const uint8_t *p, size_t n, size_t *need) {
  if (s->resyncing) {
    const size_t i = find_magic(p, n);
    if (i > 0) {
      s->stats.bytes_skipped += i;
      return i;
    }
    if (n < sizeof kMagic) { /* a magic prefix at the end: wait */
      *need = sizeof kMagic;
      return 0;
    }
    s->resyncing = 0; /* found a magic: a header is expected here */
  }
  pv_usb_frame_header_t h;
  int bad = memcmp(p, kMagic, min_size(n, sizeof kMagic)) != 0;
  if (!bad) {
    if (n < PV_USB_HEADER_BYTES) {
      *need = PV_USB_HEADER_BYTES;
      return 0;
    }
    bad = pv_usb_frame_parse_header(p, n, &h) != PV_USB_PARSE_OK;
  }
  if (bad) {
    s->stats.headers_bad++;
    s->stats.bytes_skipped++;
    s->resyncing = 1;
    return 1;
  }
  const size_t len = PV_USB_FRAME_BYTES(h.point_count);
  if (n < len) {
    *need = len;
    return 0;
  }
  if (!pv_usb_frame_crc_ok(p, h.point_count)) {
    /* Resume at the second byte: a corrupt count must not swallow the
     * frames that follow. */
    s->stats.frames_bad_crc++;
    s->stats.bytes_skipped++;
    s->resyncing = 1;
    return 1;
  }
  accept_frame(s, p, &h);
  return len;
}

void pv_usb_stream_init(pv_usb_stream_t *s, float max_abs_mm, pv_usb_points_fn on_points,
                        void *user) {
  if (s == NULL) return;
  s->fill = 0;
  /* max_abs_mm <= 0 or NaN: no range limit (non-finite points still go). */
  s->max_abs_mm = max_abs_mm > 0.0f ? max_abs_mm : FLT_MAX;
  s->have_sequence = 0;
  s->last_sequence = 0;
  s->on_points = on_points;
  s->user = user;
  memset(&s->stats, 0, sizeof s->stats);
  s->resyncing = 0;
  s->last_end_of_scan = 0;
}

void pv_usb_stream_feed(pv_usb_stream_t *s, const uint8_t *data, size_t len) {
  if (s == NULL || data == NULL || len == 0) return;
  s->stats.bytes_in += len;
  size_t pos = 0;
  size_t need = 0;

  /* A frame that straddled feeds: work in the buffer until it is used up.
   * After a rejection the buffer may hold further candidates; off walks
   * over them without moving bytes, and only before appending is the rest
   * moved to the front. */
  size_t off = 0;
  while (off < s->fill) {
    const size_t r = step(s, s->frame + off, s->fill - off, &need);
    if (r > 0) {
      off += r;
      continue;
    }
    if (off > 0) {
      memmove(s->frame, s->frame + off, s->fill - off);
      s->fill -= off;
      off = 0;
    }
    if (pos == len) return;
    const size_t take = min_size(need - s->fill, len - pos);
    memcpy(s->frame + s->fill, data + pos, take);
    s->fill += take;
    pos += take;
  }
  s->fill = 0;

  /* In place: whole frames are parsed from the caller's bytes. */
  while (pos < len) {
    const size_t r = step(s, data + pos, len - pos, &need);
    if (r > 0) {
      pos += r;
      continue;
    }
    memcpy(s->frame, data + pos, len - pos); /* < need <= MAX_FRAME_BYTES */
    s->fill = len - pos;
    pos = len;
  }
}

size_t pv_usb_stream_drop_partial(pv_usb_stream_t *s) {
  if (s == NULL) return 0;
  const size_t n = s->fill;
  s->stats.bytes_skipped += n;
  s->fill = 0;
  /* What comes next starts a fresh stream: a header is expected. */
  s->resyncing = 0;
  return n;
}
