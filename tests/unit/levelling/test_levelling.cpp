// Levelling: Rodrigues rotation, the hash sample, and recovery of a known
// tilt (0-30 deg and upside down) with 30 % outliers inside the pit.
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "levelling/hash_sample.h"
#include "levelling/levelling.h"
#include "levelling/plane_fit.h"
#include "levelling/rodrigues.h"
#include "common/point_hash.h"
#include "synth/synthetic_pit.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

constexpr double kPi = 3.14159265358979323846;

double angle_deg(const Eigen::Vector3d &a, const Eigen::Vector3d &b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
}

void rodrigues_maps_normal_onto_z(void **) {
  const Eigen::Vector3d ns[] = {{0, 0, 1}, {0.3, -0.2, 0.9}, {1, 0, 0}, {0, -1, 1e-9},
                                {0.01, 0.02, -1}, {0, 0, -1}, {-0.5, 0.5, -0.2}};
  for (const Eigen::Vector3d &n : ns) {
    const Eigen::Matrix3d R = pv::levelling::rotation_onto_z(n);
    const Eigen::Vector3d z = R * n.normalized();
    assert_true(angle_deg(z, Eigen::Vector3d::UnitZ()) < 1e-9);
    // A rotation: orthonormal with determinant +1.
    assert_true((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    assert_true(std::fabs(R.determinant() - 1.0) < 1e-12);
  }
}

void hash_sample_is_order_independent(void **) {
  std::vector<pv::P3> pts;
  for (int i = 0; i < 5000; ++i) pts.push_back(pv::P3{float(i), float(i % 7), float(i % 13)});
  pv::levelling::SampleEntry a[256], b[256], ca[256], cb[256];
  pv::levelling::HashSample s1, s2;
  s1.init(a, 256);
  s2.init(b, 256);
  for (const pv::P3 &p : pts) s1.offer(p, pv::point_hash(p));
  for (size_t i = pts.size(); i-- > 0;) s2.offer(pts[i], pv::point_hash(pts[i]));
  s1.canonical(ca);
  s2.canonical(cb);
  assert_int_equal(s1.size(), 256);
  for (int i = 0; i < 256; ++i) assert_true(ca[i].hash == cb[i].hash);
  // The sample holds the 256 smallest hashes of all points.
  std::vector<uint64_t> all;
  for (const pv::P3 &p : pts) all.push_back(pv::point_hash(p));
  std::sort(all.begin(), all.end());
  for (int i = 0; i < 256; ++i) assert_true(ca[i].hash == all[size_t(i)]);
}

// A scan sent five times over, each copy in another order, keeps the
// sample a single copy keeps: the 256 smallest distinct hashes, each once
// (without the set, copies of the smaller hashes take the slots and about
// a fifth of the sample is distinct). Many entries leave the sample on the
// way, so the set's deletion is exercised too.
void hash_sample_keeps_points_distinct(void **) {
  constexpr uint32_t k = 256;
  std::vector<pv::P3> pts;
  for (int i = 0; i < 5000; ++i) pts.push_back(pv::P3{float(i) * 0.5f, float(i % 11), float(i % 17)});
  std::vector<uint64_t> set1(pv::levelling::HashSample::set_slots_for(k)), set5(set1.size());
  assert_true(set1.size() >= 2 * k && (set1.size() & (set1.size() - 1)) == 0);
  pv::levelling::SampleEntry a[k], b[k], c[k], ca[k], cb[k], cc[k];
  pv::levelling::HashSample once, five, plain;
  once.init(a, k, set1.data());
  five.init(b, k, set5.data());
  plain.init(c, k);
  for (const pv::P3 &p : pts) once.offer(p, pv::point_hash(p));
  for (int copy = 0; copy < 5; ++copy) {
    for (size_t j = 0; j < pts.size(); ++j) {
      // Copy 0 forwards, 1 backwards, the others strided.
      const size_t i = copy == 0 ? j : copy == 1 ? pts.size() - 1 - j : (j * 7919u * copy) % pts.size();
      five.offer(pts[i], pv::point_hash(pts[i]));
      plain.offer(pts[i], pv::point_hash(pts[i]));
    }
  }
  once.canonical(ca);
  five.canonical(cb);
  plain.canonical(cc);
  std::vector<uint64_t> all;
  for (const pv::P3 &p : pts) all.push_back(pv::point_hash(p));
  std::sort(all.begin(), all.end());
  assert_int_equal(five.size(), k);
  for (uint32_t i = 0; i < k; ++i) {
    assert_true(cb[i].hash == all[i]);
    assert_true(ca[i].hash == cb[i].hash);
    assert_memory_equal(&ca[i].p, &cb[i].p, sizeof ca[i].p);
  }
  uint32_t distinct = 1;
  for (uint32_t i = 1; i < k; ++i) distinct += cc[i].hash != cc[i - 1].hash;
  assert_true(distinct < k / 2);  // what the set is for
  // clear() empties the set with the sample: the same points enter again.
  five.clear();
  for (const pv::P3 &p : pts) five.offer(p, pv::point_hash(p));
  five.canonical(cb);
  assert_int_equal(five.size(), k);
  for (uint32_t i = 0; i < k; ++i) assert_true(cb[i].hash == all[i]);
}

// A floor scanned twice, 2 mm apart along its normal (tracking slipped):
// both copies lie inside the wide band (2.5 mm), whose least-squares plane
// falls between them, where the narrow band (0.6 mm) holds no point and the
// fit would fail. The plane must be the denser copy's, tilted as the floor is.
void doubled_floor_gives_the_denser_copy(void **) {
  pv::test::Rng rng{7};
  const Eigen::Vector3d n = Eigen::Vector3d(0.1, -0.05, 1.0).normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 3000; ++i) {
    const double offset = i % 5 < 3 ? 0.0 : 2.0;  // 60 % on the lower copy
    const double a = 200.0 * (rng.uniform() - 0.5), b = 200.0 * (rng.uniform() - 0.5);
    pts.push_back(a * u + b * v + (offset + 0.05 * rng.gauss()) * n);
  }
  pv::levelling::RansacParams rp;
  rp.tol_mm = 2.5;
  pv::levelling::Plane plane;
  const uint32_t used = pv::levelling::fit_surface_plane(pts.data(), pts.size(), rp, 0.6, &plane);
  assert_int_equal(used, 1800);
  const Eigen::Vector3d up = plane.n.dot(n) < 0 ? Eigen::Vector3d(-plane.n) : plane.n;
  assert_true(angle_deg(up, n) < 0.05);
  assert_true(std::fabs(plane.d) < 0.01);  // the lower copy: through the origin
}

struct Case {
  double tilt_deg, azimuth_deg;
  bool upside_down;
  double ground_mm;
};

// True up axis of the synthetic pit in the scanner frame (see synth).
Eigen::Vector3d true_up(const Case &c) {
  const double t = c.tilt_deg * kPi / 180, az = c.azimuth_deg * kPi / 180;
  const Eigen::Vector3d up(std::sin(az) * std::sin(t), -std::cos(az) * std::sin(t), std::cos(t));
  return c.upside_down ? Eigen::Vector3d(-up) : up;
}

void recovers_tilt_with_30_percent_outliers(void **) {
  const Case cases[] = {{0, 0, false, 60},   {5, 10, false, 60},  {12, 30, false, 0},
                        {20, 100, false, 60}, {25, 200, false, 0}, {30, 290, false, 60},
                        {30, 45, false, 0},   {0, 0, true, 60},    {10, 70, true, 0},
                        {25, 150, true, 60}};
  const size_t n = 8192;
  std::vector<pv::P3> pts(n);
  std::vector<Eigen::Vector3d> a(n), b(n), c(n);
  std::vector<double> v(n);
  for (const Case &cs : cases) {
    pv::synth::PitSpec spec;
    spec.tilt_deg = cs.tilt_deg;
    spec.tilt_azimuth_deg = cs.azimuth_deg;
    spec.upside_down = cs.upside_down;
    spec.ground_width_mm = cs.ground_mm;
    spec.multipath_share = 0.30;  // 30 % outliers floating in the pit
    spec.noise_mm = 0.1;
    spec.seed = 7;
    pv::synth::PitScan scan(spec);
    for (pv::P3 &p : pts) {
      const pv_point_t q = scan.next();
      p = pv::P3{q.x_mm, q.y_mm, q.z_mm};
    }
    pv::levelling::Transform t;
    pv::levelling::Report rep;
    const auto st = pv::levelling::estimate(pts.data(), n, pv::levelling::Params{},
                                            {a.data(), b.data(), c.data(), v.data()}, &t, &rep);
    assert_true(st == pv::levelling::Status::Ok);
    const Eigen::Vector3d up = t.R.row(2).transpose();
    const double err = angle_deg(up, true_up(cs));
    if (err >= 0.05) print_error("tilt %.1f az %.0f flip %d: axis off by %.4f deg\n", cs.tilt_deg,
                                 cs.azimuth_deg, int(cs.upside_down), err);
    assert_true(err < 0.05);
    assert_true(std::fabs(t.tilt_deg() - (cs.upside_down ? 180 - cs.tilt_deg : cs.tilt_deg)) < 0.05);
  }
}

void too_few_points_is_reported(void **) {
  pv::P3 pts[10] = {};
  Eigen::Vector3d a[10], b[10], c[10];
  double v[10];
  pv::levelling::Transform t;
  pv::levelling::Report rep;
  assert_true(pv::levelling::estimate(pts, 10, pv::levelling::Params{}, {a, b, c, v}, &t, &rep) ==
              pv::levelling::Status::TooFewPoints);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(rodrigues_maps_normal_onto_z),
      cmocka_unit_test(hash_sample_is_order_independent),
      cmocka_unit_test(hash_sample_keeps_points_distinct),
      cmocka_unit_test(recovers_tilt_with_30_percent_outliers),
      cmocka_unit_test(too_few_points_is_reported),
      cmocka_unit_test(doubled_floor_gives_the_denser_copy),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
