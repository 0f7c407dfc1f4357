// Density arithmetic against values worked by hand (as exact fractions),
// units and ranges included.
#include <cmath>

#include "pitvol/density.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void near(double got, double want) {
  if (std::fabs(got - want) > 1e-9 * std::fabs(want) + 1e-12) {
    print_error("got %.12f, want %.12f\n", got, want);
    fail();
  }
}

pv_density_input_t pit() {
  // 3000 g of wet soil from a 1500 cm3 pit, +/- 30 cm3; w = 12.5 %;
  // Proctor maximum dry density 1850 kg/m3.
  pv_density_input_t in{};
  in.volume_cm3 = 1500.0;
  in.interval_cm3 = 30.0;
  in.has_mass = 1;
  in.mass_g = 3000.0;
  in.has_moisture = 1;
  in.moisture_percent = 12.5;
  in.reference_max_dry_kg_m3 = 1850.0;
  return in;
}

void densities_match_the_hand_worked_example(void **) {
  pv_density_t d;
  const pv_density_input_t in = pit();
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  assert_int_equal(d.flags, PV_DENSITY_WET | PV_DENSITY_DRY | PV_DENSITY_COMPACTION);
  // wet = 3000 g / 1500 cm3 = 2 g/cm3 = 2000 kg/m3
  near(d.wet_kg_m3, 2000.0);
  // at V + dV: 3000/1530 g/cm3 = 100/51; at V - dV: 3000/1470 = 100/49
  near(d.wet_low_kg_m3, 100000.0 / 51.0);   // 1960.784313725
  near(d.wet_high_kg_m3, 100000.0 / 49.0);  // 2040.816326531
  // dry = wet / 1.125 = wet * 8/9
  near(d.dry_kg_m3, 16000.0 / 9.0);         // 1777.777777778
  near(d.dry_low_kg_m3, 800000.0 / 459.0);  // 1742.919389978
  near(d.dry_high_kg_m3, 800000.0 / 441.0); // 1814.058956916
  // RC = dry / 1850 * 100
  near(d.compaction_percent, 1600000.0 / 16650.0);      // 96.096096096
  near(d.compaction_low_percent, 80000000.0 / 849150.0);  // 94.211858918
  near(d.compaction_high_percent, 80000000.0 / 815850.0); // 98.057240914
  assert_true(d.wet_low_kg_m3 < d.wet_kg_m3 && d.wet_kg_m3 < d.wet_high_kg_m3);
}

void units_convert_to_the_usual_field_units(void **) {
  // Water: 1000 kg/m3 = 1 g/cm3 = 62.42796 lb/ft3.
  near(pv_density_kg_m3_to_g_cm3(1000.0), 1.0);
  assert_true(std::fabs(pv_density_kg_m3_to_lb_ft3(1000.0) - 62.42796) < 1e-5);
  near(pv_density_kg_m3_to_lb_ft3(2000.0), 2.0 * pv_density_kg_m3_to_lb_ft3(1000.0));
}

void missing_inputs_give_what_can_be_computed(void **) {
  pv_density_t d;
  pv_density_input_t in = pit();
  in.has_mass = 0;  // no mass: nothing, and no error
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  assert_int_equal(d.flags, 0);
  in = pit();
  in.has_moisture = 0;  // wet only
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  assert_int_equal(d.flags, PV_DENSITY_WET);
  near(d.wet_kg_m3, 2000.0);
  assert_true(d.dry_kg_m3 == 0.0);
  in = pit();
  in.reference_max_dry_kg_m3 = 0.0;  // no reference: no compaction
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  assert_int_equal(d.flags, PV_DENSITY_WET | PV_DENSITY_DRY);
  in = pit();
  in.moisture_percent = 0.0;  // dry soil: dry = wet
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  near(d.dry_kg_m3, 2000.0);
  in = pit();
  in.interval_cm3 = 0.0;  // exact volume: a point, not a range
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  near(d.wet_low_kg_m3, 2000.0);
  near(d.wet_high_kg_m3, 2000.0);
}

void an_interval_as_wide_as_the_volume_has_no_upper_bound(void **) {
  pv_density_t d;
  pv_density_input_t in = pit();
  in.interval_cm3 = 1500.0;
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  assert_true(d.flags & PV_DENSITY_UNBOUNDED);
  near(d.wet_low_kg_m3, 1000.0);  // 3000 g / 3000 cm3
  assert_true(d.wet_high_kg_m3 == 0.0);
  assert_true(d.dry_high_kg_m3 == 0.0);
}

void bad_inputs_are_refused_with_a_reason(void **) {
  pv_density_t d;
  struct Case {
    void (*edit)(pv_density_input_t &);
    pv_density_status_t want;
  } cases[] = {
      {[](pv_density_input_t &i) { i.volume_cm3 = 0.0; }, PV_DENSITY_ERR_VOLUME},
      {[](pv_density_input_t &i) { i.volume_cm3 = NAN; }, PV_DENSITY_ERR_VOLUME},
      {[](pv_density_input_t &i) { i.interval_cm3 = -1.0; }, PV_DENSITY_ERR_VOLUME},
      {[](pv_density_input_t &i) { i.mass_g = 0.0; }, PV_DENSITY_ERR_MASS},
      {[](pv_density_input_t &i) { i.mass_g = -5.0; }, PV_DENSITY_ERR_MASS},
      {[](pv_density_input_t &i) { i.moisture_percent = -0.1; }, PV_DENSITY_ERR_MOISTURE},
      {[](pv_density_input_t &i) { i.moisture_percent = 101.0; }, PV_DENSITY_ERR_MOISTURE},
      // Absurd masses (a board took these and logged 4e305 % compaction).
      {[](pv_density_input_t &i) { i.mass_g = 1e308; }, PV_DENSITY_ERR_MASS},
      {[](pv_density_input_t &i) { i.mass_g = 1e-300; }, PV_DENSITY_ERR_MASS},
      {[](pv_density_input_t &i) { i.mass_g = 49.0; }, PV_DENSITY_ERR_MASS},
      {[](pv_density_input_t &i) { i.mass_g = 100001.0; }, PV_DENSITY_ERR_MASS},
      // In range alone, but no soil: 30 kg in 1.5 litres, or 0.5 kg.
      {[](pv_density_input_t &i) { i.mass_g = 30000.0; }, PV_DENSITY_ERR_IMPLAUSIBLE},
      {[](pv_density_input_t &i) { i.mass_g = 500.0; }, PV_DENSITY_ERR_IMPLAUSIBLE},
      {[](pv_density_input_t &i) { i.reference_max_dry_kg_m3 = 3000.0; }, PV_DENSITY_ERR_REFERENCE},
      {[](pv_density_input_t &i) { i.reference_max_dry_kg_m3 = 1.85; }, PV_DENSITY_ERR_REFERENCE},
      {[](pv_density_input_t &i) { i.reference_max_dry_kg_m3 = INFINITY; }, PV_DENSITY_ERR_REFERENCE},
  };
  for (const auto &c : cases) {
    pv_density_input_t in = pit();
    c.edit(in);
    d.flags = 99;
    assert_int_equal(pv_density_compute(&in, &d), c.want);
    assert_int_equal(d.flags, 0);
    assert_non_null(pv_density_status_message(c.want));
  }
  assert_int_equal(pv_density_compute(nullptr, &d), PV_DENSITY_ERR_INVALID_ARGUMENT);
}

// The verdict against a required compaction: the worked example's
// compaction is 96.10 % (94.21 .. 98.06) of 1850 kg/m3.
void verdict_follows_the_compaction_range(void **) {
  pv_density_t d;
  pv_density_input_t in = pit();
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  double within = -1;
  assert_int_equal(pv_density_verdict(&d, in.volume_cm3, 94.0, &within), PV_VERDICT_PASS);
  assert_true(within == 0.0);
  assert_int_equal(pv_density_verdict(&d, in.volume_cm3, 98.5, &within), PV_VERDICT_FAIL);
  assert_int_equal(pv_density_verdict(&d, in.volume_cm3, 95.0, &within), PV_VERDICT_UNDECIDED);
  // RC = 95 % at V* = 1500 x 96.10 / 95 = 1517.5 cm3: an interval under
  // +/- 17.5 cm3 (not 30) would decide.
  near(within, 1500.0 * d.compaction_percent / 95.0 - 1500.0);
  assert_int_equal(pv_density_verdict(&d, in.volume_cm3, 0.0, nullptr), PV_VERDICT_NONE);
  in.reference_max_dry_kg_m3 = 0;  // no reference: no compaction, no verdict
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  assert_int_equal(pv_density_verdict(&d, in.volume_cm3, 95.0, nullptr), PV_VERDICT_NONE);
  assert_string_equal(pv_verdict_name(PV_VERDICT_UNDECIDED), "UNDECIDED");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(densities_match_the_hand_worked_example),
      cmocka_unit_test(units_convert_to_the_usual_field_units),
      cmocka_unit_test(missing_inputs_give_what_can_be_computed),
      cmocka_unit_test(an_interval_as_wide_as_the_volume_has_no_upper_bound),
      cmocka_unit_test(bad_inputs_are_refused_with_a_reason),
      cmocka_unit_test(verdict_follows_the_compaction_range),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
