// The reference 2.5D grid (host_tools/peers/grid25.h) on analytic pits
// sampled on regular lattices, against the exact volume, with tolerances
// derived from where a mean-height grid can err (see each test).
#include <cmath>
#include <vector>

#include "grid25.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::peers::Grid25Params;
using pv::peers::Grid25Result;
using pv::peers::LevelledPoint;

constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 100.0, kD = 150.0, kGround = 40.0;

// Lattice of spacing s = cell / 4, at the centres of sub-cells: every grid
// cell holds 16 points placed symmetrically about its centre, so the mean
// of a linear height is its value at the cell centre.
template <class F>
void lattice(double cell, double extent, F &&f) {
  const double s = cell / 4;
  const long n = long(std::ceil(extent / cell)) * 4;
  for (long j = -n; j < n; ++j) {
    for (long i = -n; i < n; ++i) f((double(i) + 0.5) * s, (double(j) + 0.5) * s);
  }
}

// Inverted cone: z = D r / R inside R, ground at z = D out to R + 40.
// Exact void below the lid z = D: pi R^2 D / 3.
std::vector<LevelledPoint> cone(double cell, double hole_r = 0) {
  std::vector<LevelledPoint> pts;
  lattice(cell, kR + kGround, [&](double x, double y) {
    const double r = std::hypot(x, y);
    if (r > kR + kGround) return;
    if (hole_r > 0 && std::hypot(x - 50.0, y) < hole_r) return;  // an unseen patch
    pts.push_back({float(x), float(y), float(r < kR ? kD * r / kR : kD)});
  });
  return pts;
}

double cone_exact_cm3() { return kPi * kR * kR * kD / 3.0 / 1000.0; }

// Where the grid can err on the cone (mm3):
//  - cells across the rim circle, where the height has a kink: at most
//    8R/c + 1 such cells (a closed curve crosses at most its x- plus
//    y-variation over c cells), each off by at most slope * c over c^2;
//  - the outline is the third largest radius in the band rim-10..rim-1,
//    inside R by dr = R * 1 / D: the ring between loses at most
//    2 pi R dr * slope * dr / 2.
double cone_bound_mm3(double cell) {
  const double slope = kD / kR, dr = kR / kD;
  return (8 * kR / cell + 1) * slope * cell * cell * cell + kPi * kR * dr * slope * dr;
}

void cone_within_its_derived_bound(void **) {
  for (double cell : {1.0, 2.0}) {
    Grid25Params p;
    p.cell_mm = cell;
    const Grid25Result r = pv::peers::grid25_volume(cone(cell), kD, p);
    assert_true(r.ok);
    const double err_mm3 = (r.volume_cm3 - cone_exact_cm3()) * 1000.0;
    if (std::fabs(err_mm3) > cone_bound_mm3(cell)) {
      print_error("cell %.1f: error %.1f mm3, bound %.1f mm3\n", cell, err_mm3, cone_bound_mm3(cell));
    }
    assert_true(std::fabs(err_mm3) <= cone_bound_mm3(cell));
    assert_int_equal(r.filled_cells, 0);
  }
}

// A hole of radius h on the slope is filled ring by ring from its edge; a
// filled cell is off by at most slope * (its distance to the edge) <= slope
// * h: at most pi h^2 * slope * h more.
void a_hole_is_filled_from_its_neighbours(void **) {
  const double cell = 1.0, h = 10.0;
  const Grid25Result r = pv::peers::grid25_volume(cone(cell, h), kD, Grid25Params{});
  assert_true(r.ok);
  assert_true(r.filled_cells > 250 && r.filled_cells < 400);  // pi 10^2 = 314 cells
  const double bound = cone_bound_mm3(cell) + kPi * h * h * (kD / kR) * h;
  const double err_mm3 = (r.volume_cm3 - cone_exact_cm3()) * 1000.0;
  assert_true(std::fabs(err_mm3) <= bound);
  // Without filling the hole would count at full depth or not at all: the
  // fill must have put heights there, not zero.
  assert_true(std::fabs(err_mm3) < kPi * h * h * 50.0);
}

// Cylinder with a vertical wall: the wall's points project into the cells
// the wall circle crosses (at most 8R/c + 1), whose mean height mixes wall
// and floor; each can be off by at most D c^2. Elsewhere the grid is exact.
std::vector<LevelledPoint> cylinder(double cell, bool ground) {
  std::vector<LevelledPoint> pts;
  lattice(cell, kR + kGround, [&](double x, double y) {
    const double r = std::hypot(x, y);
    if (r < kR) pts.push_back({float(x), float(y), 0.0f});
    else if (ground && r < kR + kGround) pts.push_back({float(x), float(y), float(kD)});
  });
  for (int k = 0; k < 2880; ++k) {  // wall: every 0.125 deg, every 0.5 mm
    const double a = 2 * kPi * (k + 0.5) / 2880;
    for (double z = 0.25; z < kD; z += 0.5) {
      pts.push_back({float(kR * std::cos(a)), float(kR * std::sin(a)), float(z)});
    }
  }
  return pts;
}

void cylinder_with_and_without_ground(void **) {
  const double exact_cm3 = kPi * kR * kR * kD / 1000.0;
  for (double cell : {1.0, 2.0}) {
    for (bool ground : {true, false}) {
      Grid25Params p;
      p.cell_mm = cell;
      const Grid25Result r = pv::peers::grid25_volume(cylinder(cell, ground), kD, p);
      assert_true(r.ok);
      const double bound_mm3 = (8 * kR / cell + 1) * kD * cell * cell;
      const double err_mm3 = (r.volume_cm3 - exact_cm3) * 1000.0;
      if (std::fabs(err_mm3) > bound_mm3) {
        print_error("cell %.0f ground %d: error %.0f mm3, bound %.0f\n", cell, int(ground), err_mm3,
                    bound_mm3);
      }
      assert_true(std::fabs(err_mm3) <= bound_mm3);
      // The wall mixes in: the grid reads low, never high.
      assert_true(err_mm3 < 0);
      // Clipped to the rim outline: no cell beyond the wall counts.
      assert_true(r.outline_area_mm2 <= kPi * (kR + cell) * (kR + cell));
    }
  }
}

void refuses_without_a_wall_top(void **) {
  // Only a floor: nothing in the band below the rim, no outline.
  std::vector<LevelledPoint> pts;
  lattice(1.0, kR, [&](double x, double y) { pts.push_back({float(x), float(y), 0.0f}); });
  const Grid25Result r = pv::peers::grid25_volume(pts, kD, Grid25Params{});
  assert_false(r.ok);
  assert_true(!r.error.empty());
  assert_false(pv::peers::grid25_volume(cone(1.0), -1.0, Grid25Params{}).ok);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(cone_within_its_derived_bound),
      cmocka_unit_test(a_hole_is_filled_from_its_neighbours),
      cmocka_unit_test(cylinder_with_and_without_ground),
      cmocka_unit_test(refuses_without_a_wall_top),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
