/*
 * PSF2 console font parser (the format of Debian's console-setup fonts,
 * e.g. Lat15-TerminusBold32x16.psf). Glyph order in these fonts is not
 * ASCII order: the Unicode table says which glyph shows which code point,
 * so we read it into a Latin-1 map. Nothing is copied or allocated.
 *
 * Layout: 32-byte header (magic 72 b5 4a 86, version, header size, flags,
 * glyph count, bytes per glyph, height, width; little endian), the glyph
 * bitmaps (rows of ceil(width/8) bytes, MSB first), then if flags bit 0 is
 * set one entry per glyph: UTF-8 code points, 0xFE before a combining
 * sequence (skipped), 0xFF ending the entry.
 */
#include <string.h>

#include "pitvol/canvas.h"
#include "pitvol/le_bytes.h"

#define PSF2_MAGIC 0x864ab572u
#define PSF2_HAS_UNICODE_TABLE 0x01u

/* Decodes one UTF-8 code point at p (< end); returns bytes used (0: bad). */
static size_t utf8_decode(const uint8_t *p, const uint8_t *end, uint32_t *cp) {
  const uint8_t b = p[0];
  size_t n;
  if (b < 0x80) {
    *cp = b;
    return 1;
  }
  if ((b & 0xE0) == 0xC0) {
    n = 2;
    *cp = b & 0x1Fu;
  } else if ((b & 0xF0) == 0xE0) {
    n = 3;
    *cp = b & 0x0Fu;
  } else if ((b & 0xF8) == 0xF0) {
    n = 4;
    *cp = b & 0x07u;
  } else {
    return 0;
  }
  if ((size_t)(end - p) < n) return 0;
  for (size_t i = 1; i < n; ++i) {
    if ((p[i] & 0xC0) != 0x80) return 0;
    *cp = (*cp << 6) | (p[i] & 0x3Fu);
  }
  return n;
}

pv_display_status_t pv_font_parse_psf2(pv_font_t *f, const uint8_t *data, size_t len) {
  if (f == NULL || data == NULL) return PV_DISPLAY_ERR_INVALID_ARGUMENT;
  if (len < 32 || pv_get_le32(data) != PSF2_MAGIC) return PV_DISPLAY_ERR_FONT_FORMAT;
  const uint32_t header = pv_get_le32(data + 8), flags = pv_get_le32(data + 12), count = pv_get_le32(data + 16),
                 per_glyph = pv_get_le32(data + 20), height = pv_get_le32(data + 24), width = pv_get_le32(data + 28);
  const uint32_t row_bytes = (width + 7u) / 8u;
  if (width == 0 || height == 0 || width > 64 || height > 128 || count == 0 || count > 65536 ||
      per_glyph != row_bytes * height) {
    return PV_DISPLAY_ERR_FONT_HEADER;
  }
  if (header < 32 || header > len || (uint64_t)count * per_glyph > len - header) {
    return PV_DISPLAY_ERR_FONT_TRUNCATED;
  }
  memset(f, 0, sizeof *f);
  f->glyphs = data + header;
  f->glyph_count = count;
  f->bytes_per_glyph = per_glyph;
  f->width_px = width;
  f->height_px = height;
  f->row_bytes = row_bytes;
  int mapped[256];
  memset(mapped, 0, sizeof mapped);
  if (flags & PSF2_HAS_UNICODE_TABLE) {
    const uint8_t *p = data + header + (size_t)count * per_glyph;
    const uint8_t *end = data + len;
    for (uint32_t g = 0; g < count && p < end; ++g) {
      int in_sequence = 0;
      while (p < end && *p != 0xFF) {
        if (*p == 0xFE) {
          in_sequence = 1;
          ++p;
          continue;
        }
        uint32_t cp = 0;
        const size_t n = utf8_decode(p, end, &cp);
        if (n == 0) return PV_DISPLAY_ERR_FONT_UNICODE;
        p += n;
        if (!in_sequence && cp < 256 && !mapped[cp]) {
          f->latin1[cp] = (uint16_t)g;
          mapped[cp] = 1;
        }
      }
      if (p < end) ++p; /* the 0xFF */
    }
  } else {
    for (uint32_t cp = 0; cp < 256 && cp < count; ++cp) {
      f->latin1[cp] = (uint16_t)cp;
      mapped[cp] = 1;
    }
  }
  if (!mapped['?'] || !mapped['0'] || !mapped['A']) return PV_DISPLAY_ERR_FONT_GLYPHS;
  for (int cp = 0; cp < 256; ++cp) {
    if (!mapped[cp]) f->latin1[cp] = f->latin1['?'];
  }
  return PV_DISPLAY_OK;
}
