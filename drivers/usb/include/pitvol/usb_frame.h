/*
 * Scanner -> board USB bulk stream, protocol v1: the frame format.
 * One header for the board's driver and for the emulated scanner.
 * docs/protocol/usb.md describes it in prose; keep the two in step.
 *
 * All fields little endian, no padding:
 *
 *   offset size  field
 *   0      4     magic         0x31465650 ("PVF1" as bytes 'P' 'V' 'F' '1')
 *   4      1     version       1
 *   5      1     flags         bit 0: END_OF_SCAN (last frame of a scan)
 *   6      2     point_count   0 .. PV_USB_MAX_POINTS
 *   8      4     sequence      frame number, from 0 at start of scan, +1 each
 *   12     8     timestamp_us  scanner clock, microseconds
 *   20     12*n  points        float32 x, y, z in millimetres, per point
 *   20+12n 4     crc32c        CRC-32C (Castagnoli) of bytes 0 .. 20+12n-1
 *
 * A frame may be split across bulk transfers or share one with the next;
 * the stream is a plain byte sequence of frames.
 */
#ifndef PITVOL_USB_FRAME_H
#define PITVOL_USB_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/crc32c.h"
#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_USB_FRAME_MAGIC 0x31465650u
#define PV_USB_FRAME_VERSION 1u
#define PV_USB_FLAG_END_OF_SCAN 0x01u
#define PV_USB_FLAGS_KNOWN 0x01u
#define PV_USB_HEADER_BYTES 20u
#define PV_USB_CRC_BYTES 4u
#define PV_USB_POINT_BYTES 12u
#define PV_USB_MAX_POINTS 4096u
#define PV_USB_FRAME_BYTES(n) (PV_USB_HEADER_BYTES + PV_USB_POINT_BYTES * (size_t)(n) + PV_USB_CRC_BYTES)
#define PV_USB_MAX_FRAME_BYTES PV_USB_FRAME_BYTES(PV_USB_MAX_POINTS)

typedef struct pv_usb_frame_header {
  uint8_t version;
  uint8_t flags;
  uint16_t point_count;
  uint32_t sequence;
  uint64_t timestamp_us;
} pv_usb_frame_header_t;

typedef enum pv_usb_parse {
  /* 0, then 251 .. 299: PV_STATUS_BASE_USB's upper half (pitvol/status_codes.h) */
  PV_USB_PARSE_OK = 0,
  PV_USB_PARSE_NEED_MORE = 251, /* fewer than PV_USB_HEADER_BYTES given */
  PV_USB_PARSE_BAD_MAGIC = 252,
  PV_USB_PARSE_BAD_VERSION = 253,
  PV_USB_PARSE_BAD_COUNT = 254, /* point_count > PV_USB_MAX_POINTS */
  PV_USB_PARSE_BAD_FLAGS = 255  /* unknown flag bits set */
} pv_usb_parse_t;
/* "PV_USB_PARSE_BAD_MAGIC", ... and what it means. Never NULL. */
const char *pv_usb_parse_name(pv_usb_parse_t p);
const char *pv_usb_parse_message(pv_usb_parse_t p);

/* pv_crc32c() (pitvol/crc32c.h) checks every frame. */

/* Writes one frame into out (cap bytes). Returns the bytes written, or 0 if
 * cap < PV_USB_FRAME_BYTES(h->point_count) or the count is too large.
 * points: point_count x 3 floats (x, y, z). */
PV_NODISCARD size_t pv_usb_frame_encode(uint8_t *out, size_t cap, const pv_usb_frame_header_t *h,
                                        const float *points);

/* Parses and checks the header at buf (len bytes available). */
PV_NODISCARD pv_usb_parse_t pv_usb_frame_parse_header(const uint8_t *buf, size_t len,
                                                      pv_usb_frame_header_t *out);

/* 1 if the CRC of the whole frame at buf (PV_USB_FRAME_BYTES(count) bytes)
 * matches, else 0. */
PV_NODISCARD int pv_usb_frame_crc_ok(const uint8_t *buf, uint16_t point_count);

/* Point i of a checked frame, decoded from the wire (no alignment needed). */
void pv_usb_frame_point(const uint8_t *frame, uint16_t i, float xyz_out[3]);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_USB_FRAME_H */
