// `pitvol measure FILE --export-levelled OUT.ply` on a synthetic pit of
// known depth: every point comes out, the floor at z = 0, the ground ring
// at the rim height the file states, and that rim is the measurement's.
//
//   test_export_levelled PATH/TO/pitvol
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "grid25.h"
#include "synth/synthetic_pit.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

std::string g_pitvol;

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

void exports_the_levelled_cloud(void **) {
  const std::string dir = "test_export_levelled.d" + std::to_string(getpid());
  const std::string scan = dir + "/scan.ply", out = dir + "/levelled.ply";
  assert_int_equal(std::system(("mkdir -p " + dir).c_str()), 0);
  pv::synth::PitSpec spec;  // tilted 12 deg, offset, ground ring 60 mm wide
  const uint64_t n = 150000;
  assert_true(pv::synth::write_scan_ply(scan.c_str(), spec, n));

  FILE *p = popen(("'" + g_pitvol + "' measure " + scan + " --json --no-progress --export-levelled " + out)
                      .c_str(), "r");
  assert_non_null(p);
  std::string json;
  char buf[4096];
  size_t k;
  while ((k = std::fread(buf, 1, sizeof buf, p)) > 0) json.append(buf, k);
  assert_int_equal(pclose(p), 0);
  const size_t at = json.find("\"depth_mm\": ");
  assert_true(at != std::string::npos);
  const double depth_mm = std::strtod(json.c_str() + at + 12, nullptr);

  std::vector<pv::peers::LevelledPoint> pts;
  double rim = 0;
  std::string err;
  assert_true(pv::peers::read_levelled_ply(out, &pts, &rim, &err));
  assert_int_equal(pts.size(), n);
  // The header's rim is the measurement's depth (printed to 6 decimals).
  assert_true(std::fabs(rim - depth_mm) < 1e-5);
  assert_true(std::fabs(rim - spec.depth_mm) < 0.2);
  // Floor points (near the axis, low) at z = 0; ground points (beyond the
  // wall) at the rim: the tilt and offset are gone.
  std::vector<double> floor_z, ground_z;
  for (const auto &q : pts) {
    const double r = std::hypot(q.x_mm, q.y_mm);
    if (r < 0.5 * spec.radius_bottom_mm && q.z_mm < 20) floor_z.push_back(q.z_mm);
    if (r > spec.radius_top_mm + 10 && r < spec.radius_top_mm + spec.ground_width_mm - 10 &&
        std::fabs(q.z_mm - rim) < 20) {
      ground_z.push_back(q.z_mm);
    }
  }
  assert_true(floor_z.size() > 1000 && ground_z.size() > 1000);
  assert_true(std::fabs(median(floor_z)) < 0.1);
  assert_true(std::fabs(median(ground_z) - rim) < 0.1);
  assert_int_equal(std::system(("rm -rf " + dir).c_str()), 0);
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: test_export_levelled PATH/TO/pitvol\n");
    return 2;
  }
  g_pitvol = argv[1];
  const struct CMUnitTest tests[] = {cmocka_unit_test(exports_the_levelled_cloud)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
