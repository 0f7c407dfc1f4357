// Ten million points through the same fixed block: the bins thin in place,
// nothing grows, and the volume stays sane.
#include <cmath>
#include <vector>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void ten_million_points_in_a_fixed_block(void **) {
  pv::synth::PitSpec spec;
  spec.seed = 21;
  TestSession t;
  const size_t block_bytes = t.bytes;
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
  // The block never changed size, and the bins hold at most their capacity.
  size_t bytes = 0;
  pv_session_size(&t.cfg, &bytes);
  assert_int_equal(bytes, block_bytes);
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
