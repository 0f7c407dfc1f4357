// pv_session_transform(): the levelling and the rim that measure() used.
#include <cmath>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void matches_the_measurement(void **) {
  // paper with and without ground (rim from the ground peak / wall top);
  // surface with ground (re-levelled on the ring). 120k points: enough for
  // both, and quick under the sanitizers.
  const struct {
    pv_method_t method;
    double ground;
  } runs[] = {{PV_METHOD_PAPER, 60.0}, {PV_METHOD_PAPER, 0.0}, {PV_METHOD_SURFACE, 60.0}};
  for (const auto &run : runs) {
    const pv_method_t method = run.method;
    const double ground = run.ground;
    pv::synth::PitSpec spec;
    spec.ground_width_mm = ground;
    TestSession t(method);
    assert_int_equal(t.push_all(scan_points(spec, 120000)), PV_OK);
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
    // The reported tilt is the floor levelling's; surface then turns the
    // ground ring level, a fraction of a degree on this pit.
    const double tilt = std::acos(R[8]) * 180 / M_PI;
    assert_true(std::fabs(tilt - r.tilt_deg) < (method == PV_METHOD_PAPER ? 1e-9 : 1.0));
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
