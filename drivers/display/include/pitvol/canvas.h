/*
 * The board's drawing surface: one canvas of palette indices (one byte per
 * pixel), a bitmap console font (PSF2, e.g. Terminus from Debian's
 * console-setup-linux) and the text the screen laid out.
 *
 * Every string drawn is also appended to the canvas's text log, one line per
 * item ("text X Y SCALE|the words"), so tests assert on what a screen said
 * rather than on pixels; the PNG backend writes it beside the image.
 * Memory: the caller hands the pixel and text buffers in (sized once at
 * start by pv_canvas_bytes); drawing never allocates.
 */
#ifndef PITVOL_CANVAS_H
#define PITVOL_CANVAS_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/display_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A small palette: high contrast on a white ground for sunlight. */
typedef enum pv_color {
  PV_COLOR_WHITE = 0,
  PV_COLOR_BLACK = 1,
  PV_COLOR_GREY = 2,
  PV_COLOR_GREEN = 3,
  PV_COLOR_AMBER = 4,
  PV_COLOR_RED = 5,
  PV_COLOR_BLUE = 6,
  PV_COLOR_COUNT = 7
} pv_color_t;

/* 0xRRGGBB of each palette entry (shared by every backend). */
extern const uint32_t pv_palette_rgb[PV_COLOR_COUNT];

/* A parsed PSF2 font. The glyph bitmaps stay in the caller's bytes. */
typedef struct pv_font {
  const uint8_t *glyphs;
  uint32_t glyph_count;
  uint32_t bytes_per_glyph;
  uint32_t width_px, height_px;
  uint32_t row_bytes;
  uint16_t latin1[256]; /* code point 0..255 -> glyph ('?' glyph if none) */
} pv_font_t;

/* Parses a PSF2 font (uncompressed); uses its Unicode table when it has
 * one. PV_DISPLAY_OK, PV_DISPLAY_ERR_INVALID_ARGUMENT or one of
 * PV_DISPLAY_ERR_FONT_* (pv_display_status_message says which fault). */
PV_NODISCARD pv_display_status_t pv_font_parse_psf2(pv_font_t *f, const uint8_t *data, size_t len);

typedef struct pv_canvas {
  uint8_t *px;          /* width * height palette indices, row-major */
  uint16_t width, height;
  char *text;           /* the text log, NUL-terminated */
  size_t text_len, text_cap;
  int text_truncated;   /* the log ran out of room (a test must notice) */
} pv_canvas_t;

/* Bytes of memory a canvas needs (pixels + text_cap of text log). */
size_t pv_canvas_bytes(uint16_t width, uint16_t height, size_t text_cap);
/* Lays the canvas out in mem (pv_canvas_bytes bytes). PV_DISPLAY_OK,
 * PV_DISPLAY_ERR_INVALID_ARGUMENT (NULL, zero size, text_cap < 2) or
 * PV_DISPLAY_ERR_CANVAS_MEMORY. */
PV_NODISCARD pv_display_status_t pv_canvas_init(pv_canvas_t *c, uint16_t width, uint16_t height,
                                                size_t text_cap, void *mem, size_t bytes);

/* Clears pixels and the text log. */
void pv_canvas_clear(pv_canvas_t *c, pv_color_t ground);
/* A filled rectangle, clipped to the canvas. */
void pv_canvas_fill(pv_canvas_t *c, int x, int y, int w, int h, pv_color_t color);
/* Draws UTF-8 text (Latin-1 range; anything else shows as '?') with its
 * top-left corner at x, y, every font pixel scaled to scale x scale, and
 * logs it. Returns the width drawn in pixels. */
int pv_canvas_text(pv_canvas_t *c, const pv_font_t *f, int scale, int x, int y, pv_color_t color,
                   const char *utf8);
/* Width in pixels that pv_canvas_text would draw. */
int pv_text_width(const pv_font_t *f, int scale, const char *utf8);
/* Appends a line to the text log without drawing (e.g. "bar 3 0.82"). */
void pv_canvas_note(pv_canvas_t *c, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_CANVAS_H */
