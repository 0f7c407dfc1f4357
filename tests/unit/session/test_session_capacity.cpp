// The surface model's capacities as configuration fields (so that the MCU
// fits its block; docs/memory.md): the
// MCU profile's block, its volume against the default configuration's, the
// workspace that overlays the levelling and warm-up scratch, and the
// validation of the new fields.
#include <cmath>
#include <cstring>
#include <vector>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void mcu_profile(pv_config_t *cfg) { pv_config_mcu(cfg); }

// The MCU profile fits the linker script's block region and is method
// surface, the default's method.
void mcu_profile_fits_its_block(void **) {
  pv_config_t cfg;
  pv_config_mcu(&cfg);
  assert_int_equal(pv_config_validate(&cfg, nullptr), PV_OK);
  assert_int_equal(cfg.method, PV_METHOD_SURFACE);
  size_t bytes = 0;
  assert_int_equal(pv_session_size(&cfg, &bytes), PV_OK);
  assert_true(bytes <= PV_MCU_BLOCK_BYTES);
  assert_true(bytes > PV_MCU_BLOCK_BYTES / 2);  // the budget is used, not a mistake
}

// On a plain synthetic pit the MCU profile reads what the default reads:
// 0.3 % is the bound against the default configuration.
void mcu_profile_measures_like_the_default(void **) {
  pv::synth::PitSpec spec;
  spec.seed = 4;
  const std::vector<pv_point_t> pts = scan_points(spec, 300000);
  TestSession def, mcu(mcu_profile);
  assert_int_equal(def.push_all(pts, 4096), PV_OK);
  assert_int_equal(mcu.push_all(pts, 4096), PV_OK);
  pv_result_t a, b;
  assert_int_equal(pv_session_finish(def.s, &a), PV_OK);
  assert_int_equal(pv_session_finish(mcu.s, &b), PV_OK);
  const double e = rel_err(b.volume_cm3, a.volume_cm3);
  if (std::fabs(e) >= 0.003) print_error("MCU vs default %.4f %%\n", 100 * e);
  assert_true(std::fabs(e) < 0.003);
  assert_true(b.points_stored < a.points_stored / 8);  // it did run on far fewer points
}

// estimate() builds the surface model over the levelling scratch and the
// warm-up buffer (docs/memory.md, the overlay); streaming on afterwards
// must give the same bits as without the estimate.
void estimate_then_more_points_gives_the_same_bits(void (*tweak)(pv_config_t *)) {
  pv::synth::PitSpec spec;
  spec.seed = 6;
  const std::vector<pv_point_t> pts = scan_points(spec, 200000);
  TestSession plain(tweak), probed(tweak);
  pv_result_t a, b, e;
  assert_int_equal(plain.push_all(pts, 4096), PV_OK);
  assert_int_equal(pv_session_finish(plain.s, &a), PV_OK);
  assert_int_equal(probed.push_all(std::vector<pv_point_t>(pts.begin(), pts.begin() + 60000), 4096), PV_OK);
  assert_int_equal(pv_session_estimate(probed.s, &e), PV_OK);
  assert_int_equal(probed.push_all(std::vector<pv_point_t>(pts.begin() + 60000, pts.end()), 4096), PV_OK);
  assert_int_equal(pv_session_finish(probed.s, &b), PV_OK);
  assert_memory_equal(&a.volume_cm3, &b.volume_cm3, sizeof(double));
  assert_memory_equal(&a.interval_cm3, &b.interval_cm3, sizeof(double));
  assert_memory_equal(&a.tilt_deg, &b.tilt_deg, sizeof(double));
}
void estimate_overlay_default(void **) { estimate_then_more_points_gives_the_same_bits(nullptr); }
void estimate_overlay_mcu(void **) { estimate_then_more_points_gives_the_same_bits(mcu_profile); }

void surface_capacities_are_validated(void **) {
  struct Bad {
    const char *field;
    void (*set)(pv_config_t *);
  } bad[] = {
      {"surface_floor_points", [](pv_config_t *c) { c->surface_floor_points = 0; }},
      {"surface_theta_bins", [](pv_config_t *c) { c->surface_theta_bins = 8; }},
      {"surface_wall_dz_mm", [](pv_config_t *c) { c->surface_wall_dz_mm = NAN; }},
      {"surface_cell_mm", [](pv_config_t *c) { c->surface_cell_mm = 0.0f; }},
      {"surface_max_radius_mm", [](pv_config_t *c) { c->surface_max_radius_mm = 1.0e9f; }},
      {"surface_band_mm", [](pv_config_t *c) { c->surface_band_mm = -1.0f; }},
      {"surface_coarse_bins", [](pv_config_t *c) { c->surface_coarse_bins = 2; }},
  };
  for (const Bad &b : bad) {
    pv_config_t cfg;
    pv_config_default(&cfg);
    b.set(&cfg);
    const char *field = nullptr;
    assert_int_equal(pv_config_validate(&cfg, &field), PV_ERR_INVALID_CONFIG);
    assert_non_null(field);
    assert_string_equal(field, b.field);
    size_t bytes = 0;
    assert_int_equal(pv_session_size(&cfg, &bytes), PV_ERR_INVALID_CONFIG);
  }
}

// The overlay and the dropped layer order make the default block smaller,
// and the capacities size it: a coarser wall grid needs less.
void capacities_size_the_block(void **) {
  pv_config_t cfg;
  pv_config_default(&cfg);
  size_t full = 0, coarse = 0;
  assert_int_equal(pv_session_size(&cfg, &full), PV_OK);
  cfg.surface_theta_bins = 90;
  cfg.surface_wall_dz_mm = 4.0f;
  assert_int_equal(pv_session_size(&cfg, &coarse), PV_OK);
  assert_true(coarse < full);
  assert_true(full < size_t(48) << 20);  // 960 mm of depth range (docs/memory.md)
}

}  // namespace

int main() {
  const CMUnitTest tests[] = {
      cmocka_unit_test(mcu_profile_fits_its_block),
      cmocka_unit_test(mcu_profile_measures_like_the_default),
      cmocka_unit_test(estimate_overlay_default),
      cmocka_unit_test(estimate_overlay_mcu),
      cmocka_unit_test(surface_capacities_are_validated),
      cmocka_unit_test(capacities_size_the_block),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
