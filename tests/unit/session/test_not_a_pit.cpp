// Plausibility (issue 9): what is not one open pit gets no volume. Each
// cloud below once measured PV_OK (or would have): a random cloud, a closed
// sphere shell, a plane, a mound (a solid cylinder on the ground: levelled
// upside down it looks like a pit), two pits in one scan, and a trench
// longer than the grids. A real pit beside them still measures.
#include <cmath>
#include <vector>

#include "session_support.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::kPi;
using pv::test::Rng;

pv_point_t P(double x, double y, double z) { return pv_point_t{float(x), float(y), float(z)}; }

pv_status_t measure(const std::vector<pv_point_t> &pts) {
  TestSession t;
  t.push_all(pts, 4096);
  pv_result_t r;
  return pv_session_finish(t.s, &r);
}

void expect_refused(const std::vector<pv_point_t> &pts, const char *what) {
  const pv_status_t st = measure(pts);
  if (st == PV_OK) fail_msg("%s measured as a pit", what);
}

void random_cloud_is_refused(void **) {
  Rng g{1};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    v.push_back(P(400 * g.uniform() - 200, 400 * g.uniform() - 200, 400 * g.uniform() - 200));
  }
  expect_refused(v, "a random cloud");
}

void sphere_shell_is_refused(void **) {
  Rng g{2};
  std::vector<pv_point_t> v;
  for (int i = 0; i < 100000; ++i) {
    const double x = g.gauss(), y = g.gauss(), z = g.gauss(), n = std::sqrt(x * x + y * y + z * z);
    v.push_back(P(150 * x / n, 150 * y / n, 150 * z / n));
  }
  expect_refused(v, "a sphere shell");
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
  expect_refused(v, "a mound");
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
  expect_refused(v, "two pits");
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
  expect_refused(v, "a 1.2 m trench");
}

void one_pit_measures(void **) {
  Rng g{7};
  std::vector<pv_point_t> v;
  add_pit(g, 0, 150000, &v);
  assert_int_equal(measure(v), PV_OK);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(random_cloud_is_refused),
      cmocka_unit_test(sphere_shell_is_refused),
      cmocka_unit_test(plane_is_refused),
      cmocka_unit_test(mound_is_refused),
      cmocka_unit_test(two_pits_are_refused),
      cmocka_unit_test(trench_wider_than_the_grids_is_refused),
      cmocka_unit_test(one_pit_measures),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
