/*
 * Linux framebuffer backend: /dev/fbN mapped once at open; present()
 * converts the canvas into the mapping (pv_fb_blit) at the top-left corner.
 * 16-bit (RGB565) and 32-bit (XRGB8888) true-colour layouts, read from the
 * driver's bitfields rather than assumed.
 */
#include <errno.h>
#include <fcntl.h>
#include <linux/fb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include "display_backend.h"

typedef struct fbdev_display {
  struct pv_display base;
  int fd;
  uint8_t *map;
  size_t map_bytes;
  size_t line_bytes;
  size_t visible; /* byte offset of the visible page in the mapping */
  pv_fb_format_t fmt;
} fbdev_display_t;

static pv_display_status_t fbdev_present(pv_display_t *d, const pv_canvas_t *c, const char *screen,
                                         char *err, size_t errcap) {
  (void)screen;
  fbdev_display_t *f = (fbdev_display_t *)d;
  const pv_display_status_t st = pv_fb_blit(c, &f->fmt, f->map + f->visible, f->line_bytes);
  if (st != PV_DISPLAY_OK) snprintf(err, errcap, "framebuffer: %s", pv_display_status_message(st));
  return st;
}

static void fbdev_close(pv_display_t *d) {
  fbdev_display_t *f = (fbdev_display_t *)d;
  if (f->map != NULL && f->map != MAP_FAILED) munmap(f->map, f->map_bytes);
  if (f->fd >= 0) close(f->fd);
  free(f);
}

static const pv_display_ops_t kFbdevOps = {fbdev_present, fbdev_close};

pv_display_status_t pv_display_open_fbdev(pv_display_t **out, const char *device, uint16_t width,
                                          uint16_t height, char *err, size_t errcap) {
  fbdev_display_t *f = (fbdev_display_t *)calloc(1, sizeof *f);
  if (f == NULL) {
    snprintf(err, errcap, "display: out of memory");
    return PV_DISPLAY_ERR_NO_MEMORY;
  }
  f->base.ops = &kFbdevOps;
  f->base.width = width;
  f->base.height = height;
  f->fd = open(device, O_RDWR | O_CLOEXEC);
  if (f->fd < 0) {
    snprintf(err, errcap, "cannot open framebuffer %s: %s (check the display config and permissions)",
             device, strerror(errno));
    fbdev_close(&f->base);
    return PV_DISPLAY_ERR_OPEN;
  }
  struct fb_var_screeninfo var;
  struct fb_fix_screeninfo fix;
  if (ioctl(f->fd, FBIOGET_VSCREENINFO, &var) != 0 || ioctl(f->fd, FBIOGET_FSCREENINFO, &fix) != 0) {
    snprintf(err, errcap, "%s is not a framebuffer: %s", device, strerror(errno));
    fbdev_close(&f->base);
    return PV_DISPLAY_ERR_FB_DEVICE;
  }
  if (var.xres < width || var.yres < height) {
    snprintf(err, errcap, "framebuffer %s is %ux%u, smaller than the configured %ux%u display",
             device, var.xres, var.yres, (unsigned)width, (unsigned)height);
    fbdev_close(&f->base);
    return PV_DISPLAY_ERR_FB_DEVICE;
  }
  f->fmt.bits_per_pixel = var.bits_per_pixel;
  f->fmt.red_offset = var.red.offset;
  f->fmt.red_length = var.red.length;
  f->fmt.green_offset = var.green.offset;
  f->fmt.green_length = var.green.length;
  f->fmt.blue_offset = var.blue.offset;
  f->fmt.blue_length = var.blue.length;
  if (fix.visual != FB_VISUAL_TRUECOLOR || (var.bits_per_pixel != 16 && var.bits_per_pixel != 32)) {
    snprintf(err, errcap, "framebuffer %s has %u bits per pixel (visual %u): only 16-bit RGB565 and 32-bit XRGB8888 true colour are supported",
             device, var.bits_per_pixel, fix.visual);
    fbdev_close(&f->base);
    return PV_DISPLAY_ERR_FB_FORMAT;
  }
  f->line_bytes = fix.line_length;
  f->map_bytes = fix.smem_len;
  f->map = (uint8_t *)mmap(NULL, f->map_bytes, PROT_READ | PROT_WRITE, MAP_SHARED, f->fd, 0);
  if (f->map == MAP_FAILED) {
    snprintf(err, errcap, "cannot map framebuffer %s: %s", device, strerror(errno));
    fbdev_close(&f->base);
    return PV_DISPLAY_ERR_FB_DEVICE;
  }
  /* The visible page starts at the panning offset. */
  const size_t start = (size_t)var.yoffset * f->line_bytes + (size_t)var.xoffset * (var.bits_per_pixel / 8u);
  if (start + (size_t)height * f->line_bytes > f->map_bytes) {
    snprintf(err, errcap, "framebuffer %s mapping is smaller than its visible page", device);
    fbdev_close(&f->base);
    return PV_DISPLAY_ERR_FB_DEVICE;
  }
  f->visible = start;
  *out = &f->base;
  return PV_DISPLAY_OK;
}
