// Plausibility: what is not one open pit gets no volume (a wrong number with
// exit 0 is the worst failure an instrument has). Each cloud below would
// measure PV_OK without the checks: a random cloud, a closed
// sphere shell, a plane, a mound (a solid cylinder on the ground: levelled
// upside down it looks like a pit), two pits in one scan, and a trench
// longer than the grids. A real pit beside them still measures. Each refusal
// names the check the geometry implies, with its figure beyond its limit.
// Every case runs with each method: whether the points are one open pit does
// not depend on the method that integrates them, so the per-layer methods
// paper and polar are held to the same checks (their own checks alone
// measure all five non-pits: the random cloud 29703.0 cm3 with paper).
#include <cmath>
#include <vector>

#include "session_support.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::kPi;
using pv::test::Rng;

pv_point_t P(double x, double y, double z) { return pv_point_t{float(x), float(y), float(z)}; }

struct Outcome {
  pv_status_t status;
  pv_result_t r;
};

// The method of the running test (its cmocka state).
pv_method_t g_method = PV_METHOD_SURFACE;

int with_method(void **state) {
  g_method = *static_cast<const pv_method_t *>(*state);
  return 0;
}

Outcome measure(const std::vector<pv_point_t> &pts) {
  pv_config_t cfg;
  pv_config_default(&cfg);
  cfg.method = g_method;
  TestSession t(cfg);
  assert_int_equal(t.push_all(pts, 4096), PV_OK);
  Outcome o{};
  o.status = pv_session_finish(t.s, &o.r);
  return o;
}

// Refused, and a PV_ERR_NOT_A_PIT names a check whose figure is beyond its
// limit in the check's direction (a share or a width above, a mouth ratio
// below); want_check (if not NONE) is the check the geometry implies.
// Measured, within 1 % of exact_cm3 (not checked where it is 0).
void expect_measures(const std::vector<pv_point_t> &pts, const char *what, double exact_cm3 = 0) {
  const Outcome o = measure(pts);
  if (o.status != PV_OK) {
    fail_msg("[%s] %s: %s %s (%g against %g)", pv_method_name(g_method), what, pv_status_name(o.status),
             pv_pit_check_name(o.r.failed_check), o.r.check_value, o.r.check_limit);
  }
  if (exact_cm3 > 0 && std::fabs(o.r.volume_cm3 - exact_cm3) > 0.01 * exact_cm3) {
    fail_msg("[%s] %s: %g cm3 against %g", pv_method_name(g_method), what, o.r.volume_cm3, exact_cm3);
  }
}

void expect_refused(const std::vector<pv_point_t> &pts, const char *what,
                    pv_pit_check_t want_check = PV_PIT_CHECK_NONE) {
  const Outcome o = measure(pts);
  if (o.status == PV_OK) fail_msg("[%s] %s measured as a pit (%.1f cm3)", pv_method_name(g_method), what, o.r.volume_cm3);
  if (o.status != PV_ERR_NOT_A_PIT) {
    assert_int_equal(o.r.failed_check, PV_PIT_CHECK_NONE);
    if (want_check != PV_PIT_CHECK_NONE) {
      fail_msg("[%s] %s: %s, expected %s", pv_method_name(g_method), what, pv_status_name(o.status), pv_pit_check_name(want_check));
    }
    return;
  }
  if (want_check != PV_PIT_CHECK_NONE && o.r.failed_check != uint32_t(want_check)) {
    fail_msg("[%s] %s refused by %s (%g against %g), expected %s", pv_method_name(g_method), what,
             pv_pit_check_name(o.r.failed_check), o.r.check_value, o.r.check_limit,
             pv_pit_check_name(want_check));
  }
  switch (o.r.failed_check) {
    case PV_PIT_CHECK_POINTS_INSIDE:
    case PV_PIT_CHECK_TOO_WIDE:
    case PV_PIT_CHECK_OPENING_TILT:
    case PV_PIT_CHECK_DOUBLED_WALL:
    case PV_PIT_CHECK_DOUBLED_FLOOR:
    case PV_PIT_CHECK_DOUBLED_RIM:
    case PV_PIT_CHECK_OVER_MOUTH:
    case PV_PIT_CHECK_SHIFTED_WALL:
    case PV_PIT_CHECK_DOUBLED_SPARSE_WALL:
      if (!(o.r.check_value > o.r.check_limit)) {
        fail_msg("[%s] %s: %s figure %g not beyond %g", pv_method_name(g_method), what, pv_pit_check_name(o.r.failed_check),
                 o.r.check_value, o.r.check_limit);
      }
      break;
    case PV_PIT_CHECK_THIN_TOP:
      if (!(o.r.check_value < o.r.check_limit)) fail_msg("[%s] %s: top ratio %g", pv_method_name(g_method), what, o.r.check_value);
      break;
    case PV_PIT_CHECK_NARROW_MOUTH:
      if (!(o.r.check_value < o.r.check_limit)) fail_msg("[%s] %s: mouth %g", pv_method_name(g_method), what, o.r.check_value);
      break;
    case PV_PIT_CHECK_TOO_SMALL:
      if (!(o.r.check_value < o.r.check_limit)) fail_msg("[%s] %s: volume %g cm3", pv_method_name(g_method), what, o.r.check_value);
      break;
    case PV_PIT_CHECK_NO_POINTS: break;
    default: fail_msg("[%s] %s: PV_ERR_NOT_A_PIT without a check (%u)", pv_method_name(g_method), what, o.r.failed_check);
  }
  assert_true(o.r.volume_cm3 == 0);
}

void random_cloud_is_refused(void **) {
  Rng g{1};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    v.push_back(P(400 * g.uniform() - 200, 400 * g.uniform() - 200, 400 * g.uniform() - 200));
  }
  expect_refused(v, "a random cloud", PV_PIT_CHECK_POINTS_INSIDE);
}

void sphere_shell_is_refused(void **) {
  Rng g{2};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    const double x = g.gauss(), y = g.gauss(), z = g.gauss(), n = std::sqrt(x * x + y * y + z * z);
    v.push_back(P(150 * x / n, 150 * y / n, 150 * z / n));
  }
  expect_refused(v, "a sphere shell", PV_PIT_CHECK_NARROW_MOUTH);
}

void plane_is_refused(void **) {
  Rng g{3};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    v.push_back(P(400 * g.uniform() - 200, 400 * g.uniform() - 200, 0.3 * g.gauss()));
  }
  expect_refused(v, "a plane");
}

void mound_is_refused(void **) {
  Rng g{4};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    const double u = g.uniform(), t = 2 * kPi * g.uniform();
    if (u < 0.4) {
      const double r = 110 * std::sqrt(g.uniform());
      v.push_back(P(r * std::cos(t), r * std::sin(t), 200 + 0.1 * g.gauss()));
    } else if (u < 0.7) {
      v.push_back(P(110 * std::cos(t), 110 * std::sin(t), 200 * g.uniform()));
    } else {
      const double r = 110 + 140 * g.uniform();
      v.push_back(P(r * std::cos(t), r * std::sin(t), 0.1 * g.gauss()));
    }
  }
  expect_refused(v, "a mound", PV_PIT_CHECK_OPENING_TILT);
}

// Cylinder pits of radius 100 and depth 250 centred at (cx, 0): floor,
// wall, and (when ground) the ground between them.
void add_pit(Rng &g, double cx, int n, std::vector<pv_point_t> *v) {
  for (int i = 0; i < n; ++i) {
    const double u = g.uniform(), t = 2 * kPi * g.uniform();
    if (u < 0.45) {
      const double r = 100 * std::sqrt(g.uniform());
      v->push_back(P(cx + r * std::cos(t), r * std::sin(t), 0.1 * g.gauss()));
    } else {
      v->push_back(P(cx + 100 * std::cos(t), 100 * std::sin(t), 250 * g.uniform()));
    }
  }
}

void two_pits_are_refused(void **) {
  Rng g{5};
  std::vector<pv_point_t> v;
  add_pit(g, -150, 60000, &v);
  add_pit(g, 150, 60000, &v);
  for (int i = 0; i < 40000; ++i) {
    const double x = 600 * g.uniform() - 300, y = 300 * g.uniform() - 150;
    if (std::hypot(x - 150, y) > 100 && std::hypot(x + 150, y) > 100) v.push_back(P(x, y, 250));
  }
  expect_refused(v, "two pits", PV_PIT_CHECK_POINTS_INSIDE);
}

void trench_wider_than_the_grids_is_refused(void **) {
  Rng g{6};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 150000; ++i) {
    const double u = g.uniform();
    if (u < 0.3) {
      v.push_back(P(1200 * g.uniform() - 600, 150 * g.uniform() - 75, 0.1 * g.gauss()));
    } else if (u < 0.6) {
      v.push_back(P(1200 * g.uniform() - 600, g.uniform() < 0.5 ? -75 : 75, 200 * g.uniform()));
    } else if (u < 0.65) {
      v.push_back(P(g.uniform() < 0.5 ? -600 : 600, 150 * g.uniform() - 75, 200 * g.uniform()));
    } else {
      const double x = 1400 * g.uniform() - 700, y = 400 * g.uniform() - 200;
      if (std::fabs(x) > 600 || std::fabs(y) > 75) v.push_back(P(x, y, 200));
    }
  }
  expect_refused(v, "a 1.2 m trench", PV_PIT_CHECK_POINTS_INSIDE);
}

void one_pit_measures(void **) {
  Rng g{7};
  std::vector<pv_point_t> v;
  add_pit(g, 0, 150000, &v);
  const Outcome o = measure(v);
  if (o.status != PV_OK) fail_msg("[%s] one pit: %s", pv_method_name(g_method), pv_status_name(o.status));
  assert_int_equal(o.r.failed_check, PV_PIT_CHECK_NONE);
}

// Files carry no units. The same pit written in centimetres (7.85 L read
// as 7.85 cm3) is refused TOO_SMALL with its figure, never measured; a
// 1 L hole (radius 50 mm, 130 mm deep: the smallest test holes) in
// millimetres measures.
void pit_in_centimetres_is_refused(void **) {
  Rng g{7};
  std::vector<pv_point_t> v;
  add_pit(g, 0, 150000, &v);
  for (pv_point_t &p : v) p = P(0.1 * p.x_mm, 0.1 * p.y_mm, 0.1 * p.z_mm);
  expect_refused(v, "a pit in cm", PV_PIT_CHECK_TOO_SMALL);
  const Outcome o = measure(v);
  assert_true(std::fabs(o.r.check_value - kPi * 100 * 100 * 250 / 1e6) < 0.2);
}

void one_litre_hole_measures(void **) {
  Rng g{9};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    const double u = g.uniform(), t = 2 * kPi * g.uniform();
    if (u < 0.3) {
      const double r = 50 * std::sqrt(g.uniform());
      v.push_back(P(r * std::cos(t), r * std::sin(t), 0.1 * g.gauss()));
    } else {
      v.push_back(P(50 * std::cos(t), 50 * std::sin(t), 130 * g.uniform()));
    }
  }
  expect_measures(v, "1 L hole", kPi * 50 * 50 * 130 / 1000.0);
}

// A wall grooved all round (3 mm deep, 2 mm tall, every 5 mm: tool marks)
// puts a second surface behind the first in 0.40 of the wall's bins, like
// a scan registered twice, which the doubled-wall check's first form (the
// share of such bins, over 0.25) refused; but all round, not on two
// opposite sides: its contrast reads 0.05 (limit 0.2), one pit.
void grooved_pit_measures(void **) {
  Rng g{8};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 150000; ++i) {
    const double u = g.uniform(), t = 2 * kPi * g.uniform();
    if (u < 0.45) {
      const double r = 100 * std::sqrt(g.uniform());
      v.push_back(P(r * std::cos(t), r * std::sin(t), 0.1 * g.gauss()));
    } else {
      const double z = 250 * g.uniform();
      const double r = std::fmod(z, 5.0) < 2.0 ? 103.0 : 100.0;
      v.push_back(P(r * std::cos(t), r * std::sin(t), z));
    }
  }
  expect_measures(v, "grooved pit");
}

// n points of a cylinder pit of radius r_pit and depth h with a ground ring
// out to radius outer, raised by dz: 35 % floor, 40 % wall, 25 % ground.
void add_pit_with_ground(Rng &g, int n, double r_pit, double h, double outer, double dz,
                         std::vector<pv_point_t> *v, double dx = 0.0) {
  for (int i = 0; i < n; ++i) {
    const double u = g.uniform(), t = 2 * kPi * g.uniform();
    double r, z;
    if (u < 0.35) {
      r = r_pit * std::sqrt(g.uniform());
      z = 0.1 * g.gauss();
    } else if (u < 0.75) {
      r = r_pit;
      z = h * g.uniform();
    } else {
      r = std::sqrt(r_pit * r_pit + (outer * outer - r_pit * r_pit) * g.uniform());
      z = h + 0.1 * g.gauss();
    }
    v->push_back(P(r * std::cos(t) + dx, r * std::sin(t), z + dz));
  }
}

// A pit 760 mm across (wider than the default grids: the model is built
// again on grids scaled to it, where the doubled wall's contrast holds at
// its own limit), 200 mm deep, with a ground ring out to 480 mm:
// floor, wall and ground; copy_dz: the tracking slipped that far up after
// the first third of the scan (0: no slip).
std::vector<pv_point_t> wide_pit_with_ground(double copy_dz) {
  Rng g{11};
  std::vector<pv_point_t> v;
  add_pit_with_ground(g, 100000, 380, 200, 480, 0.0, &v);
  add_pit_with_ground(g, 200000, 380, 200, 480, copy_dz, &v);
  return v;
}

// The tracking slipped 20 mm up (issue 25 item 6): the model reads the
// later, larger pass's ground as the rim and the first pass's floor as the
// floor, 10 % more than the pit, and no other check sees it on these
// grids. The first pass's ground lies 20 mm under the rim all round.
void slipped_pass_with_ground_is_refused(void **) {
  expect_refused(wide_pit_with_ground(20.0), "a pass slipped 20 mm up", PV_PIT_CHECK_DOUBLED_RIM);
}

// Its second pass slipped 5 mm sideways: the wall twice, 5 mm apart on
// the two sides the shift points to, one on the other across them. On the
// scaled grids the contrast holds at 0.45 (real pits there up to 0.41;
// unchecked, a 5.5 mm slip read +0.81 % with PV_OK, sweep seed 1333 #324).
void wide_pit_slipped_sideways_is_refused(void **) {
  Rng g{11};
  std::vector<pv_point_t> v;
  add_pit_with_ground(g, 100000, 380, 200, 480, 0.0, &v);
  add_pit_with_ground(g, 200000, 380, 200, 480, 0.0, &v, 5.0);
  expect_refused(v, "a pass slipped 5 mm sideways", PV_PIT_CHECK_DOUBLED_WALL);
}

// The same pit scanned once measures (its ground ring has one level).
void wide_pit_with_ground_measures(void **) {
  expect_measures(wide_pit_with_ground(0.0), "wide pit", kPi * 380 * 380 * 200 / 1000.0);
}

// A pit 1.8 m across (900 mm radius, 150 mm deep, a ground ring): past the
// widest grids (2.75 x the default 320 mm, less a tenth of margin: 787.5
// mm), refused with that width as the limit, not the unscaled grids'.
void pit_past_the_widest_grids_is_refused(void **) {
  Rng g{21};
  std::vector<pv_point_t> v;
  add_pit_with_ground(g, 300000, 900, 150, 1000, 0.0, &v);
  const Outcome o = measure(v);
  assert_int_equal(o.status, PV_ERR_NOT_A_PIT);
  assert_int_equal(o.r.failed_check, PV_PIT_CHECK_TOO_WIDE);
  assert_true(o.r.check_value > 880.0);
  assert_true(std::fabs(o.r.check_limit - 2.75 * 315.0 / 1.1) < 0.01);
}

// A pit without surround, 300 mm across and 150 mm deep: a first pass of
// floor and wall, and (slip_dz not 0) a second, a fifth as large, of the
// wall from 40 mm up only, shifted slip_dz along the axis (its tracking
// slipped). The second pass sees no floor: the floor checks see nothing.
std::vector<pv_point_t> pit_with_slipped_wall_pass(double slip_dz) {
  Rng g{13};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    const double u = g.uniform(), t = 2 * kPi * g.uniform();
    if (u < 0.3) {
      const double r = 150 * std::sqrt(g.uniform());
      v.push_back(P(r * std::cos(t), r * std::sin(t), 0.1 * g.gauss()));
    } else {
      v.push_back(P(150 * std::cos(t), 150 * std::sin(t), 150 * g.uniform()));
    }
  }
  if (slip_dz == 0) return v;
  for (int i = 0; i < 20000; ++i) {
    const double t = 2 * kPi * g.uniform();
    v.push_back(P(150 * std::cos(t), 150 * std::sin(t), 40 + 110 * g.uniform() + slip_dz));
  }
  return v;
}

// The second pass slipped 25 mm up: method surface reads the rim on its
// top and the floor on the first pass's, +17 % with PV_OK without the
// thin-top check (issue 25 item 6). Above the first pass's rim only the
// second pass saw the wall: a quarter of the points per mm below. The
// per-layer methods take the rim where the wall's weight falls off, the
// first pass's top: they must refuse or read the pit.
void slipped_wall_pass_is_refused(void **) {
  const std::vector<pv_point_t> v = pit_with_slipped_wall_pass(25.0);
  if (g_method == PV_METHOD_SURFACE) {
    expect_refused(v, "a wall pass slipped 25 mm up", PV_PIT_CHECK_THIN_TOP);
    return;
  }
  const Outcome o = measure(v);
  if (o.status == PV_OK) expect_measures(v, "a wall pass slipped 25 mm up", kPi * 150 * 150 * 150 / 1000.0);
}

// The first pass alone measures.
void pit_without_surround_measures(void **) {
  expect_measures(pit_with_slipped_wall_pass(0.0), "pit without surround", kPi * 150 * 150 * 150 / 1000.0);
}

// A 1.4 L hole 100 mm across and 180 mm deep with a ground ring out to
// 110 mm: floor, wall and ground; and (slip_x not 0) a second pass, half
// as large, of the ground and the wall from 160 mm up, shifted slip_x
// sideways (its tracking slipped).
std::vector<pv_point_t> small_pit_with_ground(double slip_x) {
  Rng g{17};
  std::vector<pv_point_t> v;
  const auto add = [&](int n, double dx, double wall_from) {
    for (int i = 0; i < n; ++i) {
      const double u = g.uniform(), t = 2 * kPi * g.uniform();
      double r, z;
      if (u < 0.2 && wall_from == 0) {
        r = 50 * std::sqrt(g.uniform());
        z = 0.05 * g.gauss();
      } else if (u < 0.8) {
        r = 50;
        z = wall_from + (180 - wall_from) * g.uniform();
      } else {
        r = std::sqrt(50.0 * 50.0 + (110.0 * 110.0 - 50.0 * 50.0) * g.uniform());
        z = 180 + 0.05 * g.gauss();
      }
      v.push_back(P(r * std::cos(t) + dx, r * std::sin(t), z));
    }
  };
  add(140000, 0.0, 0.0);
  if (slip_x != 0) add(70000, slip_x, 160.0);
  return v;
}

// Slipped 18 mm sideways: the wall grid reads the outer of the two walls
// round the top, and each pass's ground lies over the other's mouth on one
// side; the copies are further apart than the doubled-wall window (8 mm).
// A scan like it read +21 % with PV_OK (tuning seed 14 #012). Method
// surface only: the per-layer methods have no such check (docs/reliability.md).
void sideways_slip_over_the_mouth_is_refused(void **) {
  expect_refused(small_pit_with_ground(18.0), "a pass slipped 18 mm sideways", PV_PIT_CHECK_OVER_MOUTH);
}

// The single pass measures.
void small_pit_with_ground_measures(void **) {
  expect_measures(small_pit_with_ground(0.0), "small pit with ground", kPi * 50 * 50 * 180 / 1000.0);
}

}  // namespace

// Each test under each method: cmocka's state is the method.
const pv_method_t kMethods[] = {PV_METHOD_SURFACE, PV_METHOD_PAPER, PV_METHOD_POLAR};
#define PV_EACH_METHOD(f)                                                                   \
  cmocka_unit_test_prestate_setup_teardown(f, with_method, nullptr, const_cast<pv_method_t *>(&kMethods[0])), \
  cmocka_unit_test_prestate_setup_teardown(f, with_method, nullptr, const_cast<pv_method_t *>(&kMethods[1])), \
  cmocka_unit_test_prestate_setup_teardown(f, with_method, nullptr, const_cast<pv_method_t *>(&kMethods[2]))

int main() {
  const struct CMUnitTest tests[] = {
      PV_EACH_METHOD(random_cloud_is_refused),
      PV_EACH_METHOD(sphere_shell_is_refused),
      PV_EACH_METHOD(plane_is_refused),
      PV_EACH_METHOD(mound_is_refused),
      PV_EACH_METHOD(two_pits_are_refused),
      PV_EACH_METHOD(trench_wider_than_the_grids_is_refused),
      PV_EACH_METHOD(one_pit_measures),
      PV_EACH_METHOD(grooved_pit_measures),
      PV_EACH_METHOD(pit_in_centimetres_is_refused),
      PV_EACH_METHOD(one_litre_hole_measures),
      PV_EACH_METHOD(slipped_pass_with_ground_is_refused),
      PV_EACH_METHOD(wide_pit_slipped_sideways_is_refused),
      PV_EACH_METHOD(wide_pit_with_ground_measures),
      PV_EACH_METHOD(pit_past_the_widest_grids_is_refused),
      PV_EACH_METHOD(slipped_wall_pass_is_refused),
      PV_EACH_METHOD(pit_without_surround_measures),
      cmocka_unit_test_prestate_setup_teardown(sideways_slip_over_the_mouth_is_refused, with_method, nullptr,
                                               const_cast<pv_method_t *>(&kMethods[0])),
      PV_EACH_METHOD(small_pit_with_ground_measures),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
