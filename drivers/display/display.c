/*
 * Display driver front (display.h): picks the backend from the spec and
 * converts canvases to framebuffer pixel layouts.
 */
#include <stdio.h>
#include <string.h>

#include "display_backend.h"

_Static_assert(PV_DISPLAY_ERR_INVALID_ARGUMENT > PV_STATUS_BASE_DISPLAY &&
                   PV_DISPLAY_ERR_FONT_GLYPHS < PV_STATUS_BASE_INPUT,
               "pv_display_status_t in its range (pitvol/status_codes.h)");

const char *pv_display_status_name(pv_display_status_t status) {
  switch (status) {
    case PV_DISPLAY_OK: return "PV_DISPLAY_OK";
    case PV_DISPLAY_ERR_INVALID_ARGUMENT: return "PV_DISPLAY_ERR_INVALID_ARGUMENT";
    case PV_DISPLAY_ERR_SPEC: return "PV_DISPLAY_ERR_SPEC";
    case PV_DISPLAY_ERR_NO_MEMORY: return "PV_DISPLAY_ERR_NO_MEMORY";
    case PV_DISPLAY_ERR_OPEN: return "PV_DISPLAY_ERR_OPEN";
    case PV_DISPLAY_ERR_FB_DEVICE: return "PV_DISPLAY_ERR_FB_DEVICE";
    case PV_DISPLAY_ERR_FB_FORMAT: return "PV_DISPLAY_ERR_FB_FORMAT";
    case PV_DISPLAY_ERR_WRITE: return "PV_DISPLAY_ERR_WRITE";
    case PV_DISPLAY_ERR_PATH_TOO_LONG: return "PV_DISPLAY_ERR_PATH_TOO_LONG";
    case PV_DISPLAY_ERR_NO_PNG: return "PV_DISPLAY_ERR_NO_PNG";
    case PV_DISPLAY_ERR_CANVAS_MEMORY: return "PV_DISPLAY_ERR_CANVAS_MEMORY";
    case PV_DISPLAY_ERR_FONT_FORMAT: return "PV_DISPLAY_ERR_FONT_FORMAT";
    case PV_DISPLAY_ERR_FONT_HEADER: return "PV_DISPLAY_ERR_FONT_HEADER";
    case PV_DISPLAY_ERR_FONT_TRUNCATED: return "PV_DISPLAY_ERR_FONT_TRUNCATED";
    case PV_DISPLAY_ERR_FONT_UNICODE: return "PV_DISPLAY_ERR_FONT_UNICODE";
    case PV_DISPLAY_ERR_FONT_GLYPHS: return "PV_DISPLAY_ERR_FONT_GLYPHS";
  }
  return "PV_DISPLAY_ERR_UNKNOWN";
}

const char *pv_display_status_message(pv_display_status_t status) {
  switch (status) {
    case PV_DISPLAY_OK: return "shown";
    case PV_DISPLAY_ERR_INVALID_ARGUMENT:
      return "the display was called without a spec, with a zero size or with a canvas of "
             "another size; a caller bug";
    case PV_DISPLAY_ERR_SPEC:
      return "the display setting names no display: use fbdev:/dev/fbN on the board or "
             "png:DIR on a host";
    case PV_DISPLAY_ERR_NO_MEMORY:
      return "no memory for the display; free memory or restart the board";
    case PV_DISPLAY_ERR_OPEN:
      return "the display device or screen directory cannot be opened; check the display "
             "setting and its permissions";
    case PV_DISPLAY_ERR_FB_DEVICE:
      return "the framebuffer is not usable (not a framebuffer, smaller than the configured "
             "display, or not mappable); check the display, display_width and display_height "
             "settings";
    case PV_DISPLAY_ERR_FB_FORMAT:
      return "the framebuffer's pixel format is not supported; set the panel to 16-bit RGB565 "
             "or 32-bit XRGB8888 true colour";
    case PV_DISPLAY_ERR_WRITE:
      return "a screen could not be written; check that the screen directory is writable and "
             "its disk has room";
    case PV_DISPLAY_ERR_PATH_TOO_LONG:
      return "the screen directory's path is too long; use a shorter png:DIR";
    case PV_DISPLAY_ERR_NO_PNG:
      return "this build has no PNG display (libpng was not found for the target); use "
             "fbdev:/dev/fbN, or build with libpng";
    case PV_DISPLAY_ERR_CANVAS_MEMORY:
      return "the canvas got less memory than pv_canvas_bytes asks for; a caller bug";
    case PV_DISPLAY_ERR_FONT_FORMAT:
      return "not a PSF2 font (too short or bad magic; PSF1 and gzip are not read): gunzip "
             "a console-setup .psf.gz font first";
    case PV_DISPLAY_ERR_FONT_HEADER:
      return "the PSF2 header has an implausible glyph size or count; use another font file";
    case PV_DISPLAY_ERR_FONT_TRUNCATED:
      return "the PSF2 font is truncated (its glyphs run past the end); copy the font again";
    case PV_DISPLAY_ERR_FONT_UNICODE:
      return "the PSF2 font's Unicode table has invalid UTF-8; use another font file";
    case PV_DISPLAY_ERR_FONT_GLYPHS:
      return "the PSF2 font lacks basic Latin glyphs ('?', '0', 'A'); use a Latin font such "
             "as Terminus Lat15";
  }
  return "unknown display status";
}

pv_display_status_t pv_display_open(pv_display_t **out, const char *spec, uint16_t width,
                                    uint16_t height, char *err, size_t errcap) {
  if (out == NULL || spec == NULL || width == 0 || height == 0) {
    snprintf(err, errcap, "display: no spec or zero size given");
    return PV_DISPLAY_ERR_INVALID_ARGUMENT;
  }
  *out = NULL;
  if (strncmp(spec, "png:", 4) == 0) return pv_display_open_png(out, spec + 4, width, height, err, errcap);
  if (strncmp(spec, "fbdev:", 6) == 0) {
    return pv_display_open_fbdev(out, spec + 6, width, height, err, errcap);
  }
  snprintf(err, errcap,
           "display '%s' not understood: use fbdev:/dev/fbN on the board or png:DIR on a host", spec);
  return PV_DISPLAY_ERR_SPEC;
}

pv_display_status_t pv_display_present(pv_display_t *d, const pv_canvas_t *c, const char *screen,
                                       char *err, size_t errcap) {
  if (d == NULL || c == NULL || c->width != d->width || c->height != d->height) {
    snprintf(err, errcap, "display: canvas does not match the display size");
    return PV_DISPLAY_ERR_INVALID_ARGUMENT;
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

pv_display_status_t pv_fb_blit(const pv_canvas_t *c, const pv_fb_format_t *fmt, uint8_t *fb,
                               size_t line_bytes) {
  if (c == NULL || fmt == NULL || fb == NULL) return PV_DISPLAY_ERR_INVALID_ARGUMENT;
  if (fmt->bits_per_pixel != 16 && fmt->bits_per_pixel != 32) return PV_DISPLAY_ERR_FB_FORMAT;
  if (fmt->red_length > 8 || fmt->green_length > 8 || fmt->blue_length > 8) {
    return PV_DISPLAY_ERR_FB_FORMAT;
  }
  const size_t bpp = fmt->bits_per_pixel / 8u;
  if (line_bytes < (size_t)c->width * bpp) return PV_DISPLAY_ERR_INVALID_ARGUMENT;
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
  return PV_DISPLAY_OK;
}
