// Ten million points through the same fixed block: the bins thin in place,
// nothing is written past the block, and the volume stays sane.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

// Bytes after the block the session is given, holding a pattern that must
// survive the stream: a write past the end of the block changes it.
constexpr size_t kGuardBytes = 4096;
constexpr unsigned char kGuard = 0xA5;

struct GuardedSession {
  pv_config_t cfg;
  size_t bytes = 0;
  unsigned char *block = nullptr;
  pv_session_t *s = nullptr;
  GuardedSession() {
    pv_config_default(&cfg);
    assert_int_equal(pv_session_size(&cfg, &bytes), PV_OK);
    const size_t rounded =
        (bytes + kGuardBytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
    block = static_cast<unsigned char *>(std::aligned_alloc(PV_BLOCK_ALIGN, rounded));
    assert_non_null(block);
    std::memset(block + bytes, kGuard, kGuardBytes);
    assert_int_equal(pv_session_init(&cfg, block, bytes, &s), PV_OK);
  }
  ~GuardedSession() { std::free(block); }
  size_t guard_bytes_changed() const {
    size_t changed = 0;
    for (size_t i = 0; i < kGuardBytes; ++i) changed += block[bytes + i] != kGuard;
    return changed;
  }
};

void ten_million_points_in_a_fixed_block(void **) {
  pv::synth::PitSpec spec;
  spec.seed = 21;
  GuardedSession t;
  pv::synth::PitScan scan(spec);
  std::vector<pv_point_t> batch(65536);
  const size_t total = 10000000;
  for (size_t done = 0; done < total; done += batch.size()) {
    const size_t n = std::min(batch.size(), total - done);
    for (size_t i = 0; i < n; ++i) batch[i] = scan.next();
    assert_int_equal(pv_session_push(t.s, batch.data(), n), PV_OK);
  }
  pv_result_t r;
  assert_int_equal(pv_session_finish(t.s, &r), PV_OK);
  assert_int_equal(r.points_in, total);
  // Nothing was written past the block, and the bins hold at most their
  // capacity.
  assert_int_equal(t.guard_bytes_changed(), 0);
  assert_true(r.points_stored <= uint64_t(t.cfg.max_layers) * t.cfg.points_per_layer);
  assert_true(r.warnings & PV_WARN_POINTS_THINNED);
  const double e = rel_err(r.volume_cm3, pv::synth::exact_volume_cm3(spec));
  print_message("10M points: volume %.2f cm3, error %.4f %%, stored %llu\n", r.volume_cm3, 100 * e,
                (unsigned long long)r.points_stored);
  assert_true(std::fabs(e) < 0.005);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {cmocka_unit_test(ten_million_points_in_a_fixed_block)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
