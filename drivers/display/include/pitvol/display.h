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
#include "pitvol/display_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pv_display pv_display_t;

/* PV_DISPLAY_OK, or the fault with one sentence in err that adds the
 * particulars (the device or directory, the system's reason):
 * PV_DISPLAY_ERR_INVALID_ARGUMENT, _SPEC, _NO_MEMORY, _OPEN, _FB_DEVICE,
 * _FB_FORMAT, _WRITE (screens.log), _PATH_TOO_LONG, _NO_PNG. */
PV_NODISCARD pv_display_status_t pv_display_open(pv_display_t **out, const char *spec,
                                                 uint16_t width, uint16_t height, char *err,
                                                 size_t errcap);
/* Shows the canvas; screen names the screen (file name in the PNG backend).
 * PV_DISPLAY_OK, or PV_DISPLAY_ERR_INVALID_ARGUMENT, _WRITE, _PATH_TOO_LONG,
 * _FB_FORMAT with one sentence in err. */
PV_NODISCARD pv_display_status_t pv_display_present(pv_display_t *d, const pv_canvas_t *c,
                                                    const char *screen, char *err,
                                                    size_t errcap);
void pv_display_close(pv_display_t *d);

/* Framebuffer pixel layout: one colour channel's bit offset and length. */
typedef struct pv_fb_format {
  uint32_t bits_per_pixel; /* 16 or 32 */
  uint32_t red_offset, red_length;
  uint32_t green_offset, green_length;
  uint32_t blue_offset, blue_length;
} pv_fb_format_t;

/* Converts the canvas into a framebuffer of that layout (line_bytes per
 * row); the fbdev backend's present(), exposed for tests. PV_DISPLAY_OK,
 * PV_DISPLAY_ERR_INVALID_ARGUMENT (NULL, rows shorter than the canvas) or
 * PV_DISPLAY_ERR_FB_FORMAT (a layout it does not convert to). */
PV_NODISCARD pv_display_status_t pv_fb_blit(const pv_canvas_t *c, const pv_fb_format_t *fmt,
                                            uint8_t *fb, size_t line_bytes);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_DISPLAY_H */
