/* Internal: what each display backend provides to display.c. */
#ifndef PV_DISPLAY_BACKEND_H
#define PV_DISPLAY_BACKEND_H

#include "pitvol/display.h"

typedef struct pv_display_ops {
  pv_display_status_t (*present)(pv_display_t *d, const pv_canvas_t *c, const char *screen,
                                 char *err, size_t errcap);
  void (*close)(pv_display_t *d);
} pv_display_ops_t;

/* Every backend's state begins with this. */
struct pv_display {
  const pv_display_ops_t *ops;
  uint16_t width, height;
};

pv_display_status_t pv_display_open_png(pv_display_t **out, const char *dir, uint16_t width,
                                        uint16_t height, char *err, size_t errcap);
pv_display_status_t pv_display_open_fbdev(pv_display_t **out, const char *device, uint16_t width,
                                          uint16_t height, char *err, size_t errcap);

#endif
