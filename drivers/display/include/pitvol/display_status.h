/*
 * What the display driver (display.h, canvas.h) returns: 0, or a code of
 * 701 .. 749 (PV_STATUS_BASE_DISPLAY, pitvol/status_codes.h).
 */
#ifndef PITVOL_DISPLAY_STATUS_H
#define PITVOL_DISPLAY_STATUS_H

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pv_display_status {
  PV_DISPLAY_OK = 0,
  PV_DISPLAY_ERR_INVALID_ARGUMENT = 701, /* NULL, zero size, a canvas not the display's size */
  PV_DISPLAY_ERR_SPEC = 702,             /* the spec names no backend (fbdev:, png:) */
  PV_DISPLAY_ERR_NO_MEMORY = 703,        /* the backend's state could not be allocated */
  PV_DISPLAY_ERR_OPEN = 704,             /* the framebuffer or the PNG directory cannot be opened */
  PV_DISPLAY_ERR_FB_DEVICE = 705,        /* not a framebuffer, smaller than the canvas, not mappable */
  PV_DISPLAY_ERR_FB_FORMAT = 706,        /* a pixel layout other than 16-bit or 32-bit true colour */
  PV_DISPLAY_ERR_WRITE = 707,            /* a screen's PNG or text, or screens.log, not written */
  PV_DISPLAY_ERR_PATH_TOO_LONG = 708,    /* the PNG directory or a screen's path is too long */
  PV_DISPLAY_ERR_NO_PNG = 709,           /* this build has no PNG backend (no libpng for the target) */
  PV_DISPLAY_ERR_CANVAS_MEMORY = 710,    /* pv_canvas_init got less than pv_canvas_bytes */
  PV_DISPLAY_ERR_FONT_FORMAT = 711,      /* not a PSF2 font: too short or bad magic */
  PV_DISPLAY_ERR_FONT_HEADER = 712,      /* a PSF2 header with an implausible glyph size or count */
  PV_DISPLAY_ERR_FONT_TRUNCATED = 713,   /* the glyphs run past the end of the file */
  PV_DISPLAY_ERR_FONT_UNICODE = 714,     /* the font's Unicode table has invalid UTF-8 */
  PV_DISPLAY_ERR_FONT_GLYPHS = 715       /* the font lacks '?', '0' or 'A' */
} pv_display_status_t;

/* The symbol ("PV_DISPLAY_ERR_WRITE"). Never NULL. */
const char *pv_display_status_name(pv_display_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_display_status_message(pv_display_status_t status);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_DISPLAY_STATUS_H */
