// The per-layer methods refuse a section sequence whose integral no pit of
// that depth and width can hold (PV_PIT_CHECK_SECTIONS), and still measure
// a real pit.
//
// The regression input (fuzz/corpus/session/regression-negative-volume-polar,
// a finding of fuzz_session): 3,752 raw points on which method
// polar kept 15 layers whose sections jump between 5,000 and 385,000 mm2
// from one layer to the next; the uneven-spacing Simpson rule (volume.h,
// V1) weighted some of them negatively and finish() returned PV_OK with
// -3468.5 cm3.
#include <cmath>
#include <vector>

#include "fuzz_input.h"
#include "fuzz_session_config.h"
#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void erratic_sections_are_refused(void **) {
  const std::vector<pv_point_t> pts = fuzz_input_points(PV_REGRESSION_INPUT);
  assert_int_equal(pts.size(), 3752);
  // As the harness runs it: method polar (seed bit 0 set), its small
  // configuration and the fine grids of the plausibility checks (they come
  // after the sections check, so the grids do not change what it sees).
  pv_config_t cfg;
  pv::fuzz::session_config(&cfg, PV_METHOD_POLAR, pv::fuzz::Grids::Fine);
  TestSession t(cfg);
  assert_non_null(t.s);
  assert_int_equal(pv_session_push(t.s, pts.data(), pts.size()), PV_OK);
  pv_result_t est{};
  assert_int_equal(pv_session_estimate(t.s, &est), PV_ERR_NOT_A_PIT);
  pv_result_t r{};
  assert_int_equal(pv_session_finish(t.s, &r), PV_ERR_NOT_A_PIT);
  for (const pv_result_t *x : {&est, &r}) {
    assert_int_equal(x->failed_check, PV_PIT_CHECK_SECTIONS);
    assert_true(x->check_value < 0.0);  // the integral was negative
    assert_true(x->check_limit == 1.05);
    assert_true(x->volume_cm3 == 0.0);
    assert_int_equal(x->layers_used, 15);
  }
}

// A synthetic pit (the default spec: 11 L, exact volume known) still
// measures with both per-layer methods, within 3 % of the truth.
void real_pit_passes(void **) {
  pv::synth::PitSpec spec;
  const std::vector<pv_point_t> pts = scan_points(spec, 200000);
  const double exact = pv::synth::exact_volume_cm3(spec);
  for (pv_method_t m : {PV_METHOD_PAPER, PV_METHOD_POLAR}) {
    pv_config_t cfg;
    pv_config_default(&cfg);
    cfg.method = m;
    TestSession t(cfg);
    assert_non_null(t.s);
    assert_int_equal(pv_session_push(t.s, pts.data(), pts.size()), PV_OK);
    pv_result_t r{};
    assert_int_equal(pv_session_finish(t.s, &r), PV_OK);
    assert_int_equal(r.failed_check, PV_PIT_CHECK_NONE);
    assert_true(std::fabs(r.volume_cm3 - exact) < 0.03 * exact);
  }
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(erratic_sections_are_refused),
      cmocka_unit_test(real_pit_passes),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
