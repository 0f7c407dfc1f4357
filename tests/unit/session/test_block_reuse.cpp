// The same points give the same statuses and volumes whatever the block held
// before pv_session_init() (a reused block, an earlier scan's values): the
// core must read only what it wrote.
//
// The regression input (fuzz/corpus/session/regression-stale-wall-values,
// a finding of fuzz_session_surface): a cloud whose sparse wall
// bins were all rejected as outliers left the wall grid with no seen bin,
// and the volume was integrated from values no build had written. Its first
// live estimate read PV_ERR_NOT_A_PIT on a zeroed block and PV_ERR_WALL_GAP
// on one filled with 50.0f, and the batching invariant failed on one filled
// with 20.0f.
#include <cstring>
#include <vector>

#include "fuzz_input.h"
#include "fuzz_session_config.h"
#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

// Every estimate and the finish, in order.
struct Outcome {
  std::vector<pv_status_t> status;
  std::vector<double> volume;
};

// A block holding value in every float before init, then the points with
// an estimate after the first estimate_at[i] of them, then the finish.
Outcome run(const pv_config_t &cfg, float value, const std::vector<pv_point_t> &pts,
            const std::vector<size_t> &estimate_at) {
  TestSession t(cfg, value);
  assert_non_null(t.s);
  Outcome o;
  size_t at = 0;
  for (size_t until : estimate_at) {
    assert_int_equal(pv_session_push(t.s, pts.data() + at, until - at), PV_OK);
    at = until;
    pv_result_t r{};
    o.status.push_back(pv_session_estimate(t.s, &r));
    o.volume.push_back(r.volume_cm3);
  }
  assert_int_equal(pv_session_push(t.s, pts.data() + at, pts.size() - at), PV_OK);
  pv_result_t r{};
  o.status.push_back(pv_session_finish(t.s, &r));
  o.volume.push_back(r.volume_cm3);
  return o;
}

void expect_same(const Outcome &a, const Outcome &b, float value) {
  assert_int_equal(a.status.size(), b.status.size());
  for (size_t i = 0; i < a.status.size(); ++i) {
    if (a.status[i] != b.status[i] ||
        std::memcmp(&a.volume[i], &b.volume[i], sizeof(double)) != 0) {
      fail_msg("call %zu: %s %.9f on a zeroed block, %s %.9f on one filled with %g", i,
               pv_status_name(a.status[i]), a.volume[i], pv_status_name(b.status[i]),
               b.volume[i], double(value));
    }
  }
}

void test_rejected_wall_reads_no_stale_values(void **) {
  const std::vector<pv_point_t> pts = fuzz_input_points(PV_REGRESSION_INPUT);
  assert_int_equal(pts.size(), 3689);
  // As the harness found it: its fine grids (seed bit 0 clear).
  pv_config_t fine;
  pv::fuzz::session_config(&fine, PV_METHOD_SURFACE, pv::fuzz::Grids::Fine);
  // Where the harness estimated (its seed's draws), and every 500 points.
  std::vector<size_t> every;
  for (size_t at = 500; at < pts.size(); at += 500) every.push_back(at);
  for (const std::vector<size_t> &at : {std::vector<size_t>{1256, 2691}, every}) {
    const Outcome zero = run(fine, 0.0f, pts, at);
    for (float value : {20.0f, 50.0f, 100.0f, -1.0f}) {
      expect_same(zero, run(fine, value, pts, at), value);
    }
  }
}

// A real pit, default configuration: the same figures on a dirty block.
void test_pit_same_on_a_dirty_block(void **) {
  pv::synth::PitSpec spec;
  const std::vector<pv_point_t> pts = scan_points(spec, 120000);
  const std::vector<size_t> at = {40000, 80000};
  pv_config_t cfg;
  pv_config_default(&cfg);
  const Outcome zero = run(cfg, 0.0f, pts, at);
  assert_int_equal(zero.status.back(), PV_OK);
  for (float value : {50.0f, 250.0f}) expect_same(zero, run(cfg, value, pts, at), value);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rejected_wall_reads_no_stale_values),
      cmocka_unit_test(test_pit_same_on_a_dirty_block),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
