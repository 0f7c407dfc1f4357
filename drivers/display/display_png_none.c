/* The PNG backend where libpng is not available for the target (a cross
 * build without the target's libpng): opening it says so. The board uses
 * the framebuffer backend. */
#include <stdio.h>

#include "display_backend.h"

pv_display_status_t pv_display_open_png(pv_display_t **out, const char *dir, uint16_t width,
                                        uint16_t height, char *err, size_t errcap) {
  (void)dir;
  (void)width;
  (void)height;
  *out = NULL;
  snprintf(err, errcap, "display png: this build has no PNG backend (libpng was not found "
                        "for the target); use fbdev:/dev/fbN");
  return PV_DISPLAY_ERR_NO_PNG;
}
