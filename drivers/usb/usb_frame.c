/* USB frame format v1: CRC-32C, encoder, header parser (see usb_frame.h). */
#include "pitvol/usb_frame.h"

#include <string.h>

#include "pitvol/le_bytes.h"

_Static_assert(PV_USB_PARSE_NEED_MORE > PV_STATUS_BASE_USB &&
                   PV_USB_PARSE_BAD_FLAGS < PV_STATUS_BASE_USB + PV_STATUS_RANGE,
               "pv_usb_parse_t in its range (pitvol/status_codes.h)");

/* Floats travel as their IEEE-754 bit pattern, little endian. */
static void put_f32(uint8_t *p, float f) {
  uint32_t v;
  memcpy(&v, &f, sizeof v);
  pv_put_le32(p, v);
}

static float get_f32(const uint8_t *p) {
  const uint32_t v = pv_get_le32(p);
  float f;
  memcpy(&f, &v, sizeof f);
  return f;
}

size_t pv_usb_frame_encode(uint8_t *out, size_t cap, const pv_usb_frame_header_t *h,
                           const float *points) {
  if (out == NULL || h == NULL || h->point_count > PV_USB_MAX_POINTS) return 0;
  if (h->point_count > 0 && points == NULL) return 0;
  const size_t bytes = PV_USB_FRAME_BYTES(h->point_count);
  if (cap < bytes) return 0;
  pv_put_le32(out, PV_USB_FRAME_MAGIC);
  out[4] = h->version;
  out[5] = h->flags;
  pv_put_le16(out + 6, h->point_count);
  pv_put_le32(out + 8, h->sequence);
  pv_put_le64(out + 12, h->timestamp_us);
  uint8_t *p = out + PV_USB_HEADER_BYTES;
  for (size_t i = 0; i < 3u * h->point_count; ++i, p += 4) put_f32(p, points[i]);
  pv_put_le32(p, pv_crc32c(0, out, bytes - PV_USB_CRC_BYTES));
  return bytes;
}

const char *pv_usb_parse_name(pv_usb_parse_t p) {
  switch (p) {
    case PV_USB_PARSE_OK: return "PV_USB_PARSE_OK";
    case PV_USB_PARSE_NEED_MORE: return "PV_USB_PARSE_NEED_MORE";
    case PV_USB_PARSE_BAD_MAGIC: return "PV_USB_PARSE_BAD_MAGIC";
    case PV_USB_PARSE_BAD_VERSION: return "PV_USB_PARSE_BAD_VERSION";
    case PV_USB_PARSE_BAD_COUNT: return "PV_USB_PARSE_BAD_COUNT";
    case PV_USB_PARSE_BAD_FLAGS: return "PV_USB_PARSE_BAD_FLAGS";
  }
  return "PV_USB_PARSE_UNKNOWN";
}

const char *pv_usb_parse_message(pv_usb_parse_t p) {
  switch (p) {
    case PV_USB_PARSE_OK: return "a frame header";
    case PV_USB_PARSE_NEED_MORE: return "not enough bytes for a frame header yet";
    case PV_USB_PARSE_BAD_MAGIC: return "not a frame: the magic 'PVF1' is missing";
    case PV_USB_PARSE_BAD_VERSION:
      return "a frame of a protocol version this driver does not speak; update the board";
    case PV_USB_PARSE_BAD_COUNT: return "a frame claims more points than a frame may hold";
    case PV_USB_PARSE_BAD_FLAGS: return "a frame sets flag bits this driver does not know";
  }
  return "unknown frame parse result";
}

pv_usb_parse_t pv_usb_frame_parse_header(const uint8_t *buf, size_t len,
                                         pv_usb_frame_header_t *out) {
  if (len < PV_USB_HEADER_BYTES) return PV_USB_PARSE_NEED_MORE;
  if (pv_get_le32(buf) != PV_USB_FRAME_MAGIC) return PV_USB_PARSE_BAD_MAGIC;
  if (buf[4] != PV_USB_FRAME_VERSION) return PV_USB_PARSE_BAD_VERSION;
  if ((buf[5] & ~PV_USB_FLAGS_KNOWN) != 0) return PV_USB_PARSE_BAD_FLAGS;
  const uint16_t count = (uint16_t)(buf[6] | buf[7] << 8);
  if (count > PV_USB_MAX_POINTS) return PV_USB_PARSE_BAD_COUNT;
  out->version = buf[4];
  out->flags = buf[5];
  out->point_count = count;
  out->sequence = pv_get_le32(buf + 8);
  out->timestamp_us = pv_get_le64(buf + 12);
  return PV_USB_PARSE_OK;
}

int pv_usb_frame_crc_ok(const uint8_t *buf, uint16_t point_count) {
  const size_t body = PV_USB_FRAME_BYTES(point_count) - PV_USB_CRC_BYTES;
  return pv_crc32c(0, buf, body) == pv_get_le32(buf + body);
}

void pv_usb_frame_point(const uint8_t *frame, uint16_t i, float xyz_out[3]) {
  const uint8_t *p = frame + PV_USB_HEADER_BYTES + (size_t)i * PV_USB_POINT_BYTES;
  for (int k = 0; k < 3; ++k) xyz_out[k] = get_f32(p + 4 * k);
}
