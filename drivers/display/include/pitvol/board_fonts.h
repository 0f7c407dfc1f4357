/* The board's fonts as embedded PSF2 bytes (Terminus Font, SIL OFL 1.1,
 * from Debian's console-setup-linux; see drivers/display/CMakeLists.txt).
 * Parse with pv_font_parse_psf2 at start. */
#ifndef PITVOL_BOARD_FONTS_H
#define PITVOL_BOARD_FONTS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

extern const uint8_t pv_font_10x20[];       /* body text */
extern const size_t pv_font_10x20_bytes;
extern const uint8_t pv_font_16x32[];       /* headings, big digits (scaled) */
extern const size_t pv_font_16x32_bytes;

#ifdef __cplusplus
}
#endif
#endif
