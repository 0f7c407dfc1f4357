// push(), estimate() and finish() must never allocate. This program replaces malloc & co. and the
// global operator new with counting versions (glibc's __libc_* underneath)
// and streams 300k points through a session while counting.
#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

extern "C" {
void *__libc_malloc(size_t);
void *__libc_calloc(size_t, size_t);
void *__libc_realloc(void *, size_t);
void *__libc_memalign(size_t, size_t);
void __libc_free(void *);
}

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
void note() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
}
}  // namespace

extern "C" void *malloc(size_t n) { note(); return __libc_malloc(n); }
extern "C" void *calloc(size_t a, size_t b) { note(); return __libc_calloc(a, b); }
extern "C" void *realloc(void *p, size_t n) { note(); return __libc_realloc(p, n); }
extern "C" void free(void *p) { __libc_free(p); }
extern "C" void *aligned_alloc(size_t a, size_t n) { note(); return __libc_memalign(a, n); }
extern "C" void *memalign(size_t a, size_t n) { note(); return __libc_memalign(a, n); }
extern "C" int posix_memalign(void **out, size_t a, size_t n) {
  note();
  *out = __libc_memalign(a, n);
  return *out ? 0 : 12;
}
void *operator new(size_t n) {
  note();
  if (void *p = __libc_malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void *operator new[](size_t n) { return operator new(n); }
void operator delete(void *p) noexcept { __libc_free(p); }
void operator delete[](void *p) noexcept { __libc_free(p); }
void operator delete(void *p, size_t) noexcept { __libc_free(p); }
void operator delete[](void *p, size_t) noexcept { __libc_free(p); }

namespace {

void the_counter_sees_allocations(void **) {
  // Proves the test below can fail: an allocation inside the window counts.
  g_allocations = 0;
  g_counting = true;
  int *volatile p = new int(3);
  void *volatile q = std::malloc(16);
  g_counting = false;
  delete p;
  std::free(q);
  assert_int_equal(g_allocations.load(), 2);
}

void push_never_allocates(void **) {
  pv::synth::PitSpec spec;
  const std::vector<pv_point_t> pts = scan_points(spec, 300000);
  TestSession t;  // set-up may allocate (the block itself)
  g_allocations = 0;
  g_counting = true;
  // Batches of several sizes; the warm-up, the first plane and two
  // refinements all happen inside this window.
  pv_status_t st = t.push_all(pts, 1000) == PV_OK ? PV_OK : PV_ERR_INTERNAL;
  // The scan again whole: the repeat mode's index is built (every bin
  // sorted) and each point looked up in it, tails merged on the stack.
  if (st == PV_OK) st = t.push_all(pts, 4096) == PV_OK ? PV_OK : PV_ERR_INTERNAL;
  g_counting = false;
  assert_int_equal(st, PV_OK);
  assert_int_equal(g_allocations.load(), 0);
  pv_result_t r;
  assert_int_equal(pv_session_finish(t.s, &r), PV_OK);
}

void use_paper(pv_config_t *c) { c->method = PV_METHOD_PAPER; }

// estimate() and finish() of the default method (surface) and of paper work
// in the block alone (the board has no allocator to spare): zero allocations, however often estimate()
// runs while the scan goes on.
void estimate_and_finish_never_allocate(void **) {
  pv::synth::PitSpec spec;
  const std::vector<pv_point_t> pts = scan_points(spec, 300000);
  for (int paper = 0; paper < 2; ++paper) {
    TestSession t(paper ? use_paper : nullptr);  // else the default, surface
    pv_result_t r;
    const size_t half = pts.size() / 2;
    assert_int_equal(pv_session_push(t.s, pts.data(), half), PV_OK);
    g_allocations = 0;
    g_counting = true;
    const pv_status_t e1 = pv_session_estimate(t.s, &r);
    const pv_status_t e2 = pv_session_estimate(t.s, &r);
    g_counting = false;
    assert_int_equal(e1, PV_OK);
    assert_int_equal(e2, PV_OK);
    assert_int_equal(pv_session_push(t.s, pts.data() + half, pts.size() - half), PV_OK);
    g_counting = true;
    const pv_status_t e3 = pv_session_estimate(t.s, &r);
    const pv_status_t f = pv_session_finish(t.s, &r);
    g_counting = false;
    assert_int_equal(e3, PV_OK);
    assert_int_equal(f, PV_OK);
    assert_true(r.volume_cm3 > 0);
    assert_int_equal(g_allocations.load(), 0);
  }
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(the_counter_sees_allocations),
      cmocka_unit_test(push_never_allocates),
      cmocka_unit_test(estimate_and_finish_never_allocate),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
