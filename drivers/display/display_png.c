/*
 * PNG backend for the host and the tests (libpng). Each present() writes
 * DIR/<screen>.png (8-bit palette: the canvas's indices as they are) and
 * DIR/<screen>.txt (the text log), each via a temporary file and rename()
 * so a reader never sees half a file, then appends "=== <n> <screen>" and
 * the log to DIR/screens.log (the history of every screen shown).
 *
 * No allocation after open: libpng and zlib get their working memory from
 * an arena reserved at open (png_create_write_struct_2 with our malloc_fn),
 * reset after each image; files are written with write(2), not stdio.
 */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "display_backend.h"

#define PNG_ARENA_BYTES (2u * 1024u * 1024u) /* zlib's deflate state is ~270 KB */
#define LOG_RECORD_BYTES 8192u

typedef struct png_display {
  struct pv_display base;
  char dir[PATH_MAX / 2];
  int log_fd;
  unsigned long presents;
  uint8_t *arena;
  size_t arena_used;
  int arena_exhausted;
  int fd;             /* the image being written */
  int write_failed;
  char error[256];    /* from libpng's error callback */
  char record[LOG_RECORD_BYTES];
} png_display_t;

static png_voidp arena_malloc(png_structp png, png_alloc_size_t n) {
  png_display_t *p = (png_display_t *)png_get_mem_ptr(png);
  const size_t need = ((size_t)n + 15u) & ~(size_t)15u;
  if (p->arena_used + need > PNG_ARENA_BYTES) {
    p->arena_exhausted = 1;
    return NULL;
  }
  void *r = p->arena + p->arena_used;
  p->arena_used += need;
  return r;
}

static void arena_free(png_structp png, png_voidp ptr) {
  (void)png;
  (void)ptr; /* the whole arena is reset after each image */
}

static void on_png_error(png_structp png, png_const_charp msg) {
  png_display_t *p = (png_display_t *)png_get_error_ptr(png);
  snprintf(p->error, sizeof p->error, "%s", msg);
  png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg) {
  (void)png;
  (void)msg;
}

static void on_png_write(png_structp png, png_bytep data, size_t len) {
  png_display_t *p = (png_display_t *)png_get_io_ptr(png);
  while (len > 0 && !p->write_failed) {
    const ssize_t n = write(p->fd, data, len);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      p->write_failed = 1;
      return;
    }
    data += n;
    len -= (size_t)n;
  }
}

static void on_png_flush(png_structp png) { (void)png; }

static int write_all(int fd, const void *data, size_t len) {
  const char *b = (const char *)data;
  while (len > 0) {
    const ssize_t n = write(fd, b, len);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return -1;
    b += n;
    len -= (size_t)n;
  }
  return 0;
}

/* libpng's setjmp lives here alone so no local is clobbered by longjmp. */
static int encode(png_display_t *p, const pv_canvas_t *c) {
  p->arena_used = 0;
  p->arena_exhausted = 0;
  p->error[0] = '\0';
  png_structp png = png_create_write_struct_2(PNG_LIBPNG_VER_STRING, p, on_png_error,
                                              on_png_warning, p, arena_malloc, arena_free);
  if (png == NULL) return -1;
  png_infop info = png_create_info_struct(png);
  if (info == NULL || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return -1;
  }
  png_set_write_fn(png, p, on_png_write, on_png_flush);
  png_set_IHDR(png, info, c->width, c->height, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_color palette[PV_COLOR_COUNT];
  for (int i = 0; i < PV_COLOR_COUNT; ++i) {
    palette[i].red = (png_byte)(pv_palette_rgb[i] >> 16);
    palette[i].green = (png_byte)(pv_palette_rgb[i] >> 8);
    palette[i].blue = (png_byte)pv_palette_rgb[i];
  }
  png_set_PLTE(png, info, palette, PV_COLOR_COUNT);
  png_set_filter(png, 0, PNG_FILTER_NONE); /* best for palette images */
  png_set_compression_level(png, 9);
  png_write_info(png, info);
  for (uint16_t y = 0; y < c->height; ++y) png_write_row(png, c->px + (size_t)y * c->width);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return p->write_failed ? -1 : 0;
}

/* dir/name.ext via dir/name.ext.tmp; 0 or -1. */
static int path_of(const png_display_t *p, const char *screen, const char *ext, char *out,
                   size_t cap) {
  const int n = snprintf(out, cap, "%s/%s%s", p->dir, screen, ext);
  return n > 0 && (size_t)n < cap ? 0 : -1;
}

static pv_display_status_t png_present(pv_display_t *d, const pv_canvas_t *c, const char *screen,
                                       char *err, size_t errcap) {
  png_display_t *p = (png_display_t *)d;
  char final_path[PATH_MAX], tmp[PATH_MAX];
  if (path_of(p, screen, ".png", final_path, sizeof final_path) != 0 ||
      path_of(p, screen, ".png.tmp", tmp, sizeof tmp) != 0) {
    snprintf(err, errcap, "display: PNG path too long");
    return PV_DISPLAY_ERR_PATH_TOO_LONG;
  }
  p->fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (p->fd < 0) {
    snprintf(err, errcap, "cannot write %s: %s", tmp, strerror(errno));
    return PV_DISPLAY_ERR_WRITE;
  }
  p->write_failed = 0;
  const int r = encode(p, c);
  close(p->fd);
  p->fd = -1;
  if (r != 0 || rename(tmp, final_path) != 0) {
    snprintf(err, errcap, "cannot write %s: %s", final_path,
             p->arena_exhausted ? "libpng needs more than the reserved working memory"
             : p->error[0]      ? p->error
                                : strerror(errno));
    unlink(tmp);
    return PV_DISPLAY_ERR_WRITE;
  }
  if (path_of(p, screen, ".txt", final_path, sizeof final_path) != 0 ||
      path_of(p, screen, ".txt.tmp", tmp, sizeof tmp) != 0) {
    snprintf(err, errcap, "display: text path too long");
    return PV_DISPLAY_ERR_PATH_TOO_LONG;
  }
  const int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int ok = fd >= 0 && write_all(fd, c->text, c->text_len) == 0;
  if (fd >= 0) close(fd);
  if (!ok || rename(tmp, final_path) != 0) {
    snprintf(err, errcap, "cannot write %s: %s", final_path, strerror(errno));
    return PV_DISPLAY_ERR_WRITE;
  }
  /* One write() per record: a reader of screens.log sees whole records. */
  p->presents++;
  const int n = snprintf(p->record, sizeof p->record, "=== %lu %s%s\n%s", p->presents, screen,
                         c->text_truncated ? " (text log truncated)" : "", c->text);
  const size_t len = n < 0 ? 0 : ((size_t)n < sizeof p->record ? (size_t)n : sizeof p->record - 1);
  if (write_all(p->log_fd, p->record, len) != 0) {
    snprintf(err, errcap, "cannot append to %s/screens.log: %s", p->dir, strerror(errno));
    return PV_DISPLAY_ERR_WRITE;
  }
  return PV_DISPLAY_OK;
}

static void png_close(pv_display_t *d) {
  png_display_t *p = (png_display_t *)d;
  if (p->log_fd >= 0) close(p->log_fd);
  free(p->arena);
  free(p);
}

static const pv_display_ops_t kPngOps = {png_present, png_close};

pv_display_status_t pv_display_open_png(pv_display_t **out, const char *dir, uint16_t width,
                                        uint16_t height, char *err, size_t errcap) {
  if (dir == NULL || dir[0] == '\0') {
    snprintf(err, errcap, "display png: give a directory (png:DIR)");
    return PV_DISPLAY_ERR_SPEC;
  }
  png_display_t *p = (png_display_t *)calloc(1, sizeof *p);
  if (p == NULL) {
    snprintf(err, errcap, "display: out of memory");
    return PV_DISPLAY_ERR_NO_MEMORY;
  }
  p->base.ops = &kPngOps;
  p->base.width = width;
  p->base.height = height;
  p->log_fd = -1;
  p->fd = -1;
  if ((size_t)snprintf(p->dir, sizeof p->dir, "%s", dir) >= sizeof p->dir) {
    snprintf(err, errcap, "display png: directory name too long");
    png_close(&p->base);
    return PV_DISPLAY_ERR_PATH_TOO_LONG;
  }
  if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
    snprintf(err, errcap, "cannot create the screen directory %s: %s", dir, strerror(errno));
    png_close(&p->base);
    return PV_DISPLAY_ERR_OPEN;
  }
  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s/screens.log", dir);
  p->log_fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  p->arena = (uint8_t *)malloc(PNG_ARENA_BYTES);
  if (p->arena == NULL) {
    snprintf(err, errcap, "display png: no memory for libpng's working memory");
    png_close(&p->base);
    return PV_DISPLAY_ERR_NO_MEMORY;
  }
  if (p->log_fd < 0) {
    snprintf(err, errcap, "cannot write %s: %s", path, strerror(errno));
    png_close(&p->base);
    return PV_DISPLAY_ERR_WRITE;
  }
  *out = &p->base;
  return PV_DISPLAY_OK;
}
