// Z gridding: z -> dz * round(z / dz), layer indices, range limits.
#include "gridding/gridding.h"
#include "pv_cmocka.h"

namespace {

void rounds_to_nearest_layer(void **) {
  pv::gridding::Grid g{0.5, 100, 8};
  assert_int_equal(g.layer_of(0.0), 8);
  assert_int_equal(g.layer_of(0.24), 8);
  assert_int_equal(g.layer_of(0.26), 9);
  assert_int_equal(g.layer_of(-0.26), 7);
  assert_int_equal(g.layer_of(10.0), 28);
  assert_true(g.z_of(28) == 10.0);
  // Half-way rounds up, for either sign (the same on every platform).
  assert_int_equal(g.layer_of(0.25), 9);
  assert_int_equal(g.layer_of(-0.25), 8);
}

void outside_the_grid_is_minus_one(void **) {
  pv::gridding::Grid g{0.5, 100, 8};
  assert_int_equal(g.layer_of(-4.0), 0);
  assert_int_equal(g.layer_of(-4.3), -1);
  assert_int_equal(g.layer_of(g.top_mm()), 99);
  assert_int_equal(g.layer_of(g.top_mm() + 0.3), -1);
  assert_int_equal(g.layer_of(NAN), -1);
}

void other_layer_thickness(void **) {
  pv::gridding::Grid g{0.1, 1000, pv::gridding::layers_below(0.1)};
  assert_int_equal(g.below, 40);
  assert_int_equal(g.layer_of(1.0), 50);
  pv::gridding::Grid h{2.0, 100, pv::gridding::layers_below(2.0)};
  assert_int_equal(h.below, 2);
  assert_int_equal(h.layer_of(2.9), 3);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(rounds_to_nearest_layer),
      cmocka_unit_test(outside_the_grid_is_minus_one),
      cmocka_unit_test(other_layer_thickness),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
