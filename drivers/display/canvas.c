/*
 * Drawing into the canvas (canvas.h): rectangles and bitmap text, with a
 * text log of everything written. No allocation; everything is clipped.
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "pitvol/canvas.h"

const uint32_t pv_palette_rgb[PV_COLOR_COUNT] = {
    0xFFFFFFu, /* white */
    0x000000u, /* black */
    0x808080u, /* grey */
    0x00A040u, /* green */
    0xF0A000u, /* amber */
    0xD01010u, /* red */
    0x1040C0u, /* blue */
};

size_t pv_canvas_bytes(uint16_t width, uint16_t height, size_t text_cap) {
  return (size_t)width * height + text_cap;
}

pv_display_status_t pv_canvas_init(pv_canvas_t *c, uint16_t width, uint16_t height,
                                   size_t text_cap, void *mem, size_t bytes) {
  if (c == NULL || mem == NULL || width == 0 || height == 0 || text_cap < 2) {
    return PV_DISPLAY_ERR_INVALID_ARGUMENT;
  }
  if (bytes < pv_canvas_bytes(width, height, text_cap)) return PV_DISPLAY_ERR_CANVAS_MEMORY;
  c->px = (uint8_t *)mem;
  c->width = width;
  c->height = height;
  c->text = (char *)mem + (size_t)width * height;
  c->text_cap = text_cap;
  pv_canvas_clear(c, PV_COLOR_WHITE);
  return PV_DISPLAY_OK;
}

void pv_canvas_clear(pv_canvas_t *c, pv_color_t ground) {
  memset(c->px, (int)ground, (size_t)c->width * c->height);
  c->text[0] = '\0';
  c->text_len = 0;
  c->text_truncated = 0;
}

void pv_canvas_fill(pv_canvas_t *c, int x, int y, int w, int h, pv_color_t color) {
  int x0 = x < 0 ? 0 : x, y0 = y < 0 ? 0 : y;
  int x1 = x + w > c->width ? c->width : x + w, y1 = y + h > c->height ? c->height : y + h;
  for (int yy = y0; yy < y1; ++yy) {
    if (x1 > x0) memset(c->px + (size_t)yy * c->width + x0, (int)color, (size_t)(x1 - x0));
  }
}

static void vnote(pv_canvas_t *c, const char *fmt, va_list ap) {
  if (c->text_truncated) return;
  const size_t room = c->text_cap - c->text_len;
  const int n = vsnprintf(c->text + c->text_len, room, fmt, ap);
  if (n < 0 || (size_t)n + 1 >= room) {
    c->text[c->text_len] = '\0';
    c->text_truncated = 1;
    return;
  }
  c->text_len += (size_t)n;
  c->text[c->text_len++] = '\n';
  c->text[c->text_len] = '\0';
}

void pv_canvas_note(pv_canvas_t *c, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vnote(c, fmt, ap);
  va_end(ap);
}

/* Next code point of a UTF-8 string; malformed bytes read as '?'. */
static uint32_t next_cp(const char **s) {
  const unsigned char *p = (const unsigned char *)*s;
  if (p[0] < 0x80) {
    *s += 1;
    return p[0];
  }
  if ((p[0] & 0xE0) == 0xC0 && (p[1] & 0xC0) == 0x80) {
    *s += 2;
    return ((uint32_t)(p[0] & 0x1F) << 6) | (p[1] & 0x3Fu);
  }
  *s += 1;
  while ((**s & 0xC0) == 0x80) *s += 1; /* skip the rest of a longer sequence */
  return '?';
}

int pv_text_width(const pv_font_t *f, int scale, const char *utf8) {
  int n = 0;
  while (*utf8) {
    (void)next_cp(&utf8);
    ++n;
  }
  return n * (int)f->width_px * scale;
}

static void glyph(pv_canvas_t *c, const pv_font_t *f, int scale, int x, int y, pv_color_t color,
                  uint32_t cp) {
  const uint8_t *g = f->glyphs + (size_t)f->latin1[cp < 256 ? cp : '?'] * f->bytes_per_glyph;
  for (uint32_t row = 0; row < f->height_px; ++row) {
    const uint8_t *bits = g + row * f->row_bytes;
    for (uint32_t col = 0; col < f->width_px; ++col) {
      if (bits[col >> 3] & (0x80u >> (col & 7u))) {
        pv_canvas_fill(c, x + (int)col * scale, y + (int)row * scale, scale, scale, color);
      }
    }
  }
}

int pv_canvas_text(pv_canvas_t *c, const pv_font_t *f, int scale, int x, int y, pv_color_t color,
                   const char *utf8) {
  pv_canvas_note(c, "text %d %d %d|%s", x, y, scale * (int)f->height_px, utf8);
  int cx = x;
  const char *s = utf8;
  while (*s) {
    glyph(c, f, scale, cx, y, color, next_cp(&s));
    cx += (int)f->width_px * scale;
  }
  return cx - x;
}
