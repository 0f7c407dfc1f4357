// The opening as a support plane (method surface's last way to level a
// scan): a sparse ground ring in a frame far from level, strays above it,
// and what must not be taken for an opening.
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "rim/support_plane.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::kPi;
using pv::test::Rng;

constexpr double kRadius = 150.0, kDepth = 300.0, kGroundOuter = 175.0;
constexpr size_t kPoints = 8192;

struct Pit {
  double ground_share;  // of the points, on the ground ring
  double stray_share;   // of the points, floating up to 40 mm above it
};

// A cylinder pit (floor at z = 0, rim at kDepth) with a ground ring, 0.1 mm
// noise, seen in a frame rotated by tilt_deg about the axis (1, 1, 0).
std::vector<Eigen::Vector3d> scan(const Pit &pit, double tilt_deg, Rng &r) {
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(tilt_deg * kPi / 180.0, Eigen::Vector3d(1, 1, 0).normalized())
          .toRotationMatrix();
  std::vector<Eigen::Vector3d> pts;
  const double floor_area = kPi * kRadius * kRadius, wall_area = 2 * kPi * kRadius * kDepth;
  const double floor_share = (1.0 - pit.ground_share - pit.stray_share) * floor_area /
                             (floor_area + wall_area);
  for (size_t i = 0; i < kPoints; ++i) {
    const double u = r.uniform(), th = 2 * kPi * r.uniform();
    Eigen::Vector3d p;
    if (u < pit.ground_share) {
      const double rr = kRadius + (kGroundOuter - kRadius) * r.uniform();
      p = {rr * std::cos(th), rr * std::sin(th), kDepth + 0.1 * r.gauss()};
    } else if (u < pit.ground_share + pit.stray_share) {
      const double rr = kGroundOuter * std::sqrt(r.uniform());
      p = {rr * std::cos(th), rr * std::sin(th), kDepth + 3.5 + 36.5 * r.uniform()};
    } else if (u < pit.ground_share + pit.stray_share + floor_share) {
      const double rr = kRadius * std::sqrt(r.uniform());
      p = {rr * std::cos(th), rr * std::sin(th), 0.1 * r.gauss()};
    } else {
      const double rr = kRadius + 0.1 * r.gauss();
      p = {rr * std::cos(th), rr * std::sin(th), kDepth * r.uniform()};
    }
    pts.push_back(rot * p);
  }
  return pts;
}

pv::rim::SupportPlane fit(const std::vector<Eigen::Vector3d> &pts, double max_tilt_deg) {
  std::vector<double> z(pts.size());
  std::vector<uint32_t> idx(pts.size() + pv::rim::kSupportIndexExtra);
  return pv::rim::fit_support_plane(pts.data(), pts.size(), max_tilt_deg, z.data(), idx.data());
}

Eigen::Vector3d true_up(double tilt_deg) {
  return Eigen::AngleAxisd(tilt_deg * kPi / 180.0, Eigen::Vector3d(1, 1, 0).normalized()) *
         Eigen::Vector3d::UnitZ();
}

void a_sparse_ground_25_degrees_off_is_found(void **) {
  // 0.7 % of the points on the ground, as a deep pit's in the sweeps: under
  // a quarter of any top band, so fit_ground_plane() does not find it.
  Rng r{11};
  const auto pts = scan(Pit{0.007, 0.003}, 25.0, r);
  const pv::rim::SupportPlane sp = fit(pts, 30.0);
  assert_true(sp.found);
  const double err_deg = std::acos(std::fmin(1.0, sp.normal.dot(true_up(25.0)))) * 180.0 / kPi;
  assert_true(err_deg < 0.2);
  assert_true(std::fabs(sp.d - kDepth) < 0.2);  // the rotation is about the origin
  assert_true(sp.on >= 50);
}

void a_level_ground_reads_its_height(void **) {
  Rng r{12};
  const pv::rim::SupportPlane sp = fit(scan(Pit{0.05, 0.003}, 0.0, r), 30.0);
  assert_true(sp.found);
  assert_true(sp.normal.z() > std::cos(0.05 * kPi / 180.0));
  assert_true(std::fabs(sp.d - kDepth) < 0.05);
}

void many_points_above_are_no_opening(void **) {
  // 4 % of the points float above the ground: the plane under them is not
  // the top of the scan, and no plane is reported rather than a guess.
  Rng r{13};
  assert_false(fit(scan(Pit{0.02, 0.04}, 5.0, r), 30.0).found);
}

void beyond_the_allowed_tilt_is_not_found(void **) {
  Rng r{14};
  const auto pts = scan(Pit{0.02, 0.003}, 40.0, r);
  assert_false(fit(pts, 30.0).found);
  assert_true(fit(pts, 45.0).found);  // the same scan, allowed further
}

void too_few_points(void **) {
  std::vector<Eigen::Vector3d> pts(40, Eigen::Vector3d(1, 2, 3));
  assert_false(fit(pts, 30.0).found);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(a_sparse_ground_25_degrees_off_is_found),
      cmocka_unit_test(a_level_ground_reads_its_height),
      cmocka_unit_test(many_points_above_are_no_opening),
      cmocka_unit_test(beyond_the_allowed_tilt_is_not_found),
      cmocka_unit_test(too_few_points),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
