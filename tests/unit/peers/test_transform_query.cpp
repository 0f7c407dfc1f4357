// pv_session_transform(): the levelling and the rim that measure() used.
#include <cmath>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void matches_the_measurement(void **) {
  for (double ground : {60.0, 0.0}) {
    pv::synth::PitSpec spec;
    spec.ground_width_mm = ground;
    TestSession t;
    assert_int_equal(t.push_all(scan_points(spec, 200000), 4096), PV_OK);
    pv_result_t r;
    assert_int_equal(pv_session_finish(t.s, &r), PV_OK);
    pv_transform_t tf;
    assert_int_equal(pv_session_transform(t.s, &tf), PV_OK);
    // The same rim as the measurement, bit for bit, from the same source.
    assert_true(tf.rim_mm == r.depth_mm);
    assert_int_equal(tf.rim_from_ground, ground > 0 ? 1u : 0u);
    // The ground peak is the lid (the wall-top estimate without ground is
    // measure()'s own, a few mm off on this scan: docs/accuracy.md).
    if (ground > 0) assert_true(std::fabs(tf.rim_mm - spec.depth_mm) < 0.2);
    // A rotation (orthonormal, det +1) whose tilt is the reported one.
    const double *R = tf.rotation;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        double d = 0;
        for (int k = 0; k < 3; ++k) d += R[3 * a + k] * R[3 * b + k];
        assert_true(std::fabs(d - (a == b ? 1.0 : 0.0)) < 1e-9);
      }
    }
    assert_true(std::fabs(std::acos(R[8]) * 180 / M_PI - r.tilt_deg) < 1e-9);
    // Asked again, the same bits (it only reads the sample and the bins).
    pv_transform_t again;
    assert_int_equal(pv_session_transform(t.s, &again), PV_OK);
    assert_memory_equal(&tf, &again, sizeof tf);
  }
}

void errors(void **) {
  pv_transform_t tf;
  assert_int_equal(pv_session_transform(nullptr, &tf), PV_ERR_INVALID_ARGUMENT);
  TestSession t;
  assert_int_equal(pv_session_transform(t.s, nullptr), PV_ERR_INVALID_ARGUMENT);
  assert_int_equal(pv_session_transform(t.s, &tf), PV_ERR_TOO_FEW_POINTS);  // nothing pushed
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(matches_the_measurement),
      cmocka_unit_test(errors),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
