/* USB frame format v1: CRC-32C, encoder, header parser (see usb_frame.h). */
#include "pitvol/usb_frame.h"

#include <string.h>

static void put_u16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)v;
  p[1] = (uint8_t)(v >> 8);
}

static void put_u32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = (uint8_t)(v >> (8 * i));
}

static void put_u64(uint8_t *p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get_u32(const uint8_t *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t get_u64(const uint8_t *p) {
  return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32;
}

/* Floats travel as their IEEE-754 bit pattern, little endian. */
static void put_f32(uint8_t *p, float f) {
  uint32_t v;
  memcpy(&v, &f, sizeof v);
  put_u32(p, v);
}

static float get_f32(const uint8_t *p) {
  const uint32_t v = get_u32(p);
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
  put_u32(out, PV_USB_FRAME_MAGIC);
  out[4] = h->version;
  out[5] = h->flags;
  put_u16(out + 6, h->point_count);
  put_u32(out + 8, h->sequence);
  put_u64(out + 12, h->timestamp_us);
  uint8_t *p = out + PV_USB_HEADER_BYTES;
  for (size_t i = 0; i < 3u * h->point_count; ++i, p += 4) put_f32(p, points[i]);
  put_u32(p, pv_crc32c(0, out, bytes - PV_USB_CRC_BYTES));
  return bytes;
}

pv_usb_parse_t pv_usb_frame_parse_header(const uint8_t *buf, size_t len,
                                         pv_usb_frame_header_t *out) {
  if (len < PV_USB_HEADER_BYTES) return PV_USB_PARSE_NEED_MORE;
  if (get_u32(buf) != PV_USB_FRAME_MAGIC) return PV_USB_PARSE_BAD_MAGIC;
  if (buf[4] != PV_USB_FRAME_VERSION) return PV_USB_PARSE_BAD_VERSION;
  if ((buf[5] & ~PV_USB_FLAGS_KNOWN) != 0) return PV_USB_PARSE_BAD_FLAGS;
  const uint16_t count = (uint16_t)(buf[6] | buf[7] << 8);
  if (count > PV_USB_MAX_POINTS) return PV_USB_PARSE_BAD_COUNT;
  out->version = buf[4];
  out->flags = buf[5];
  out->point_count = count;
  out->sequence = get_u32(buf + 8);
  out->timestamp_us = get_u64(buf + 12);
  return PV_USB_PARSE_OK;
}

int pv_usb_frame_crc_ok(const uint8_t *buf, uint16_t point_count) {
  const size_t body = PV_USB_FRAME_BYTES(point_count) - PV_USB_CRC_BYTES;
  return pv_crc32c(0, buf, body) == get_u32(buf + body);
}

void pv_usb_frame_point(const uint8_t *frame, uint16_t i, float xyz_out[3]) {
  const uint8_t *p = frame + PV_USB_HEADER_BYTES + (size_t)i * PV_USB_POINT_BYTES;
  for (int k = 0; k < 3; ++k) xyz_out[k] = get_f32(p + 4 * k);
}
