/*
 * Allocation counter for the host build of the board (as in the core's
 * push test): malloc & co. are replaced by counting versions over glibc's
 * __libc_* functions, and each allocation is charged to the zone the
 * calling thread is in (board_alloc_zone.h). Not linked into the board
 * program, nor into sanitizer builds (ASan owns malloc there).
 */
#include "alloc_counter.h"

#include <stdatomic.h>
#include <stddef.h>

#include "../board_alloc_zone.h"

void *__libc_malloc(size_t);
void *__libc_calloc(size_t, size_t);
void *__libc_realloc(void *, size_t);
void *__libc_memalign(size_t, size_t);
void __libc_free(void *);

static atomic_long g_counts[PV_ZONE_COUNT];

static void note(void) {
  const int z = pv_alloc_zone;
  if (z > PV_ZONE_NONE && z < PV_ZONE_COUNT) atomic_fetch_add(&g_counts[z], 1);
}

void *malloc(size_t n) { note(); return __libc_malloc(n); }
void *calloc(size_t a, size_t b) { note(); return __libc_calloc(a, b); }
void *realloc(void *p, size_t n) { note(); return __libc_realloc(p, n); }
void free(void *p) { __libc_free(p); }
void *aligned_alloc(size_t a, size_t n) { note(); return __libc_memalign(a, n); }
void *memalign(size_t a, size_t n) { note(); return __libc_memalign(a, n); }
int posix_memalign(void **out, size_t a, size_t n) {
  note();
  *out = __libc_memalign(a, n);
  return *out ? 0 : 12;
}

long pv_alloc_count(int zone) {
  return zone > PV_ZONE_NONE && zone < PV_ZONE_COUNT ? atomic_load(&g_counts[zone]) : 0;
}
