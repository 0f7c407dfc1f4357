// A session of the core in its own aligned block, for every test that
// measures through the C ABI (tests/unit/session, tests/corpus, ...).
#ifndef PV_TESTS_TEST_SESSION_H
#define PV_TESTS_TEST_SESSION_H

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "pitvol/pitvol.h"

struct TestSession {
  pv_config_t cfg;
  size_t bytes = 0;
  void *block = nullptr;
  pv_session_t *s = nullptr;
  // tweak: adjusts the default configuration before the block is sized.
  explicit TestSession(void (*tweak)(pv_config_t *) = nullptr) : TestSession(tweak, nullptr) {}
  // The block holds fill in every float before init (a reused block).
  TestSession(void (*tweak)(pv_config_t *), float fill) : TestSession(tweak, &fill) {}
  // The configuration as given (cfg_in), not the default's.
  explicit TestSession(const pv_config_t &cfg_in) : cfg(cfg_in) { open(nullptr); }
  TestSession(const pv_config_t &cfg_in, float fill) : cfg(cfg_in) { open(&fill); }
  // The default configuration with another method.
  explicit TestSession(pv_method_t method) : TestSession(with_method(method)) {}
  ~TestSession() { std::free(block); }
  // Pushes pts in calls of batch points (all in one call: 0); the first
  // status that is not PV_OK.
  [[nodiscard]] pv_status_t push_all(const std::vector<pv_point_t> &pts, size_t batch = 0) {
    const size_t step = batch > 0 ? batch : pts.size();
    for (size_t i = 0; i < pts.size(); i += step) {
      const size_t n = pts.size() - i < step ? pts.size() - i : step;
      const pv_status_t st = pv_session_push(s, pts.data() + i, n);
      if (st != PV_OK) return st;
    }
    return PV_OK;
  }

 private:
  static pv_config_t with_method(pv_method_t method) {
    pv_config_t c;
    pv_config_default(&c);
    c.method = method;
    return c;
  }
  TestSession(void (*tweak)(pv_config_t *), const float *fill) {
    pv_config_default(&cfg);
    if (tweak != nullptr) tweak(&cfg);
    open(fill);
  }
  // A test's session must open: anything else is a broken test set-up, not
  // a result to check. Aborts (a failed test) because cmocka's asserts are
  // not declared yet here (pv_cmocka.h comes last).
  static void require(pv_status_t st, const char *what) {
    if (st == PV_OK) return;
    std::fprintf(stderr, "TestSession: %s: %s\n", what, pv_status_name(st));
    std::abort();
  }
  void open(const float *fill) {
    require(pv_session_size(&cfg, &bytes), "pv_session_size");
    const size_t rounded = (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
    block = std::aligned_alloc(PV_BLOCK_ALIGN, rounded);
    if (block == nullptr) require(PV_ERR_OUT_OF_MEMORY, "aligned_alloc");
    if (fill != nullptr) std::fill_n(static_cast<float *>(block), rounded / sizeof(float), *fill);
    require(pv_session_init(&cfg, block, bytes, &s), "pv_session_init");
  }
};

#endif
