/*
 * The board's display driver: shows a finished canvas (canvas.h).
 *
 * Backends, chosen by a spec string (board config key `display`):
 *   "fbdev:/dev/fb0"  Linux framebuffer (mmap), RGB565 or XRGB8888 (any
 *                     16/32-bit true-colour layout the driver reports);
 *                     the canvas is drawn at the top-left corner.
 *   "png:DIR"         the host and the tests: every present() writes
 *                     DIR/<screen>.png (8-bit palette) and DIR/<screen>.txt
 *                     (the canvas's text log) and appends the log to
 *                     DIR/screens.log under a "=== <n> <screen>" line.
 * Everything a backend needs (mapping, PNG rows, libpng/zlib working
 * memory) is set up in open(); present() does not allocate.
 */
#ifndef PITVOL_DISPLAY_H
#define PITVOL_DISPLAY_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/canvas.h"
#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pv_display pv_display_t;

/* 0 on success; else -1 with a sentence in err (what failed, what to do). */
PV_NODISCARD int pv_display_open(pv_display_t **out, const char *spec, uint16_t width,
                                 uint16_t height, char *err, size_t errcap);
/* Shows the canvas; screen names the screen (file name in the PNG backend).
 * 0 or -1 with a sentence in err. */
PV_NODISCARD int pv_display_present(pv_display_t *d, const pv_canvas_t *c, const char *screen,
                                    char *err, size_t errcap);
void pv_display_close(pv_display_t *d);

/* Framebuffer pixel layout: one colour channel's bit offset and length. */
typedef struct pv_fb_format {
  uint32_t bits_per_pixel; /* 16 or 32 */
  uint32_t red_offset, red_length;
  uint32_t green_offset, green_length;
  uint32_t blue_offset, blue_length;
} pv_fb_format_t;

/* Converts the canvas into a framebuffer of that layout (line_bytes per
 * row); the fbdev backend's present(), exposed for tests. 0 or -1 if the
 * layout is not supported. */
PV_NODISCARD int pv_fb_blit(const pv_canvas_t *c, const pv_fb_format_t *fmt, uint8_t *fb,
                            size_t line_bytes);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_DISPLAY_H */
