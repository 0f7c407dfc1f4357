/*
 * Display driver front (display.h): picks the backend from the spec and
 * converts canvases to framebuffer pixel layouts.
 */
#include <stdio.h>
#include <string.h>

#include "display_backend.h"

int pv_display_open(pv_display_t **out, const char *spec, uint16_t width, uint16_t height,
                    char *err, size_t errcap) {
  if (out == NULL || spec == NULL || width == 0 || height == 0) {
    snprintf(err, errcap, "display: no spec or zero size given");
    return -1;
  }
  *out = NULL;
  if (strncmp(spec, "png:", 4) == 0) return pv_display_open_png(out, spec + 4, width, height, err, errcap);
  if (strncmp(spec, "fbdev:", 6) == 0) {
    return pv_display_open_fbdev(out, spec + 6, width, height, err, errcap);
  }
  snprintf(err, errcap,
           "display '%s' not understood: use fbdev:/dev/fbN on the board or png:DIR on a host", spec);
  return -1;
}

int pv_display_present(pv_display_t *d, const pv_canvas_t *c, const char *screen, char *err,
                       size_t errcap) {
  if (d == NULL || c == NULL || c->width != d->width || c->height != d->height) {
    snprintf(err, errcap, "display: canvas does not match the display size");
    return -1;
  }
  return d->ops->present(d, c, screen != NULL ? screen : "screen", err, errcap);
}

void pv_display_close(pv_display_t *d) {
  if (d != NULL) d->ops->close(d);
}

/* Scales an 8-bit channel into a bitfield of `length` bits at `offset`. */
static uint32_t channel(uint32_t v8, uint32_t offset, uint32_t length) {
  if (length == 0) return 0;
  return ((v8 >> (8u - length)) & ((1u << length) - 1u)) << offset;
}

int pv_fb_blit(const pv_canvas_t *c, const pv_fb_format_t *fmt, uint8_t *fb, size_t line_bytes) {
  if (c == NULL || fmt == NULL || fb == NULL) return -1;
  if (fmt->bits_per_pixel != 16 && fmt->bits_per_pixel != 32) return -1;
  if (fmt->red_length > 8 || fmt->green_length > 8 || fmt->blue_length > 8) return -1;
  const size_t bpp = fmt->bits_per_pixel / 8u;
  if (line_bytes < (size_t)c->width * bpp) return -1;
  uint32_t lut[PV_COLOR_COUNT] = {0};
  for (int i = 0; i < PV_COLOR_COUNT; ++i) {
    const uint32_t rgb = pv_palette_rgb[i];
    lut[i] = channel((rgb >> 16) & 0xFFu, fmt->red_offset, fmt->red_length) |
             channel((rgb >> 8) & 0xFFu, fmt->green_offset, fmt->green_length) |
             channel(rgb & 0xFFu, fmt->blue_offset, fmt->blue_length);
  }
  for (uint16_t y = 0; y < c->height; ++y) {
    const uint8_t *src = c->px + (size_t)y * c->width;
    uint8_t *row = fb + (size_t)y * line_bytes;
    for (uint16_t x = 0; x < c->width; ++x) {
      const uint32_t v = lut[src[x] < PV_COLOR_COUNT ? src[x] : PV_COLOR_BLACK];
      if (bpp == 2) {
        const uint16_t p = (uint16_t)v;
        memcpy(row + (size_t)x * 2u, &p, 2);
      } else {
        memcpy(row + (size_t)x * 4u, &v, 4);
      }
    }
  }
  return 0;
}
