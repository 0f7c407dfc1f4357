// Hostile input to the host tools (CTest label "cli"; docs/reliability.md):
// each case with the exit code and the message the user sees.
//
//   test_cli_hostile DIR_OF_TOOLS
//
// DIR_OF_TOOLS holds pitvol, pitvol-sim, pitvol-accuracy, pitvol-synth,
// pitvol-bench and pitvol-usb-replay. Each case would have failed before the
// fix it guards: /dev/zero as --config grew without bound, a directory was
// read as an empty file, a NUL byte hid the rest of its line, an unwritable
// --layers path exited 0, "-x" was taken as a file name, 34.7 GB of
// capacities passed validation, "measure --help" was a usage error.
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "synth/synthetic_pit.h"
#include "cli_run.h"  // last: it includes pv_cmocka.h

namespace {

std::string g_tools;  // directory of the built tools
std::string g_dir;    // scratch directory of this test
std::string g_scan;   // a small valid scan (PLY)

// Runs TOOL ARGS through the shell with a 60 s limit (a tool that hangs on
// /dev/zero fails the case instead of the whole run).
Run run_tool(const std::string &tool, const std::string &args) {
  return run_command("timeout 60 " + quote(g_tools + "/" + tool) + " " + args + " </dev/null",
                     g_dir + "/stderr.txt");
}

Run pitvol(const std::string &args) { return run_tool("pitvol", args); }

void expect_contains(const std::string &text, const std::string &sub) {
  if (text.find(sub) == std::string::npos) {
    print_error("expected '%s' in: %s\n", sub.c_str(), text.c_str());
    fail();
  }
}

void expect_exit(const Run &r, int code) {
  if (r.exit_code != code) {
    print_error("exit %d, expected %d; stdout: %s\nstderr: %s\n", r.exit_code, code,
                r.out.c_str(), r.err.c_str());
    fail();
  }
}

std::string write_file(const std::string &name, const std::string &bytes) {
  const std::string path = g_dir + "/" + name;
  FILE *f = std::fopen(path.c_str(), "wb");
  assert_non_null(f);
  assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  assert_int_equal(std::fclose(f), 0);
  return path;
}

std::string measure_with_config(const std::string &config_path) {
  return "measure " + quote(g_scan) + " --config " + quote(config_path);
}

// ---- --config --------------------------------------------------------------

void config_dev_zero_is_refused_quickly(void **) {
  const Run r = pitvol(measure_with_config("/dev/zero"));
  expect_exit(r, 2);
  expect_contains(r.err, "/dev/zero: larger than 65536 bytes");
}

void config_directory_is_refused(void **) {
  const Run r = pitvol(measure_with_config(g_dir));
  expect_exit(r, 2);
  expect_contains(r.err, "is a directory");
}

void config_nul_byte_is_refused(void **) {
  const std::string path = write_file("nul.conf", std::string("layer_mm = 0.5\0junk = 7\n", 24));
  const Run r = pitvol(measure_with_config(path));
  expect_exit(r, 2);
  expect_contains(r.err, "nul.conf:1: contains a NUL byte");
}

void config_long_line_is_refused(void **) {
  const std::string path = write_file("long.conf", "# " + std::string(5000, 'x') + "\n");
  const Run r = pitvol(measure_with_config(path));
  expect_exit(r, 2);
  expect_contains(r.err, "long.conf:1: line longer than 1024 bytes");
}

void config_absurd_capacities_refused_at_validation(void **) {
  // 65536 layers x 32768 points: 2^31 slots, 34.7 GB of block.
  const std::string path = write_file("huge.conf", "max_layers = 65536\npoints_per_layer = 32768\n");
  const Run r = pitvol(measure_with_config(path));
  expect_exit(r, 2);
  expect_contains(r.err, "max_layers x points_per_layer = 2147483648 point slots");
  expect_contains(r.err, "32768 MiB");
}

void config_out_of_range_names_the_value(void **) {
  const std::string path = write_file("range.conf", "layer_mm = 9\n");
  const Run r = pitvol(measure_with_config(path));
  expect_exit(r, 2);
  expect_contains(r.err, "range.conf:1: layer_mm = 9 is outside the allowed 0.1 .. 2\n");
  assert_int_equal(std::count(r.err.begin(), r.err.end(), '\n'), 1);  // one line
}

void config_missing_file_says_why(void **) {
  const Run r = pitvol(measure_with_config(g_dir + "/no-such.conf"));
  expect_exit(r, 2);
  expect_contains(r.err, "no-such.conf: cannot open the configuration file (No such file");
}

// ---- arguments ---------------------------------------------------------------

void unknown_short_option_is_a_usage_error(void **) {
  const Run r = pitvol("measure " + quote(g_scan) + " -x");
  expect_exit(r, 2);
  expect_contains(r.err, "not expected: -x");  // CLI11's words
}

void file_named_like_an_option_after_double_dash(void **) {
  // After "--", -x is a file name: it does not exist (exit 3), it is not an
  // option.
  const Run r = run_tool("pitvol", "measure -- -no-such-file.ply");
  expect_exit(r, 3);
  expect_contains(r.err, "-no-such-file.ply");
}

void layers_to_unwritable_path_fails_before_measuring(void **) {
  const Run r = pitvol("measure " + quote(g_scan) + " --layers " +
                       quote(g_dir + "/no-such-dir/layers.csv"));
  expect_exit(r, 3);
  expect_contains(r.err, "--layers: cannot write ");
  expect_contains(r.err, "No such file or directory");
}

void layers_to_full_disk_exits_non_zero(void **) {
  struct stat st{};
  if (stat("/dev/full", &st) != 0) skip();
  const Run r = pitvol("measure " + quote(g_scan) + " --layers /dev/full");
  expect_exit(r, 3);
  expect_contains(r.err, "--layers: cannot write /dev/full: No space left on device");
}

void help_on_every_command_of_every_tool(void **) {
  const char *cases[][2] = {
      {"pitvol", "--help"},          {"pitvol", "measure --help"},
      {"pitvol", "measure x.ply -h"}, {"pitvol-sim", "--help"},
      {"pitvol-sim", "scan --help"}, {"pitvol-sim", "corpus --help"},
      {"pitvol-accuracy", "--help"}, {"pitvol-synth", "--help"},
      {"pitvol-bench", "--help"},    {"pitvol-usb-replay", "--help"},
  };
  for (const auto &c : cases) {
    const Run r = run_tool(c[0], c[1]);
    if (r.exit_code != 0 || r.out.find("usage:") == std::string::npos) {
      print_error("%s %s: exit %d, stdout '%s'\n", c[0], c[1], r.exit_code, r.out.c_str());
      fail();
    }
  }
}

// A bad command line of the tools whose main() parses with CLI11: one line
// naming what is wrong, exit 2 (they printed the whole usage text).
void argument_errors_of_every_tool_are_one_line(void **) {
  const char *cases[][3] = {
      {"pitvol-bench", "--bogus", "--bogus"},
      {"pitvol-bench", "--scale 10", "--scale"},
      {"pitvol-bench", "--scan-points 10", "--scan-points"},
      {"pitvol-accuracy", "", "DIR is required"},
      {"pitvol-accuracy", "corpus --jobs 2", "--jobs: a sweep only: give --envelope"},
      {"pitvol-accuracy", "sweep --envelope --check x.csv", "--check: not with --envelope"},
      {"pitvol-accuracy", "corpus --peers grid25,nope", "unknown peer 'nope'"},
      {"pitvol-accuracy", "sweep --envelope --method surface --method paper", "one method"},
      {"pitvol-usb-replay", "x.frames --corrupt 2", "--corrupt"},
      {"pitvol-usb-replay", "x.frames --drop nan", "not a finite number"},
      {"pitvol-usb-replay", "x.frames --fps 0", "--fps"},
  };
  for (const auto &c : cases) {
    const Run r = run_tool(c[0], c[1]);
    const bool one_line = std::count(r.err.begin(), r.err.end(), '\n') == 1;
    if (r.exit_code != 2 || !one_line || r.err.find(c[2]) == std::string::npos ||
        r.err.rfind(std::string(c[0]) + ": ", 0) != 0) {
      print_error("%s %s: exit %d, stderr '%s' (want exit 2, one line with '%s')\n", c[0], c[1],
                  r.exit_code, r.err.c_str(), c[2]);
      fail();
    }
  }
}

// ---- messages with numbers ---------------------------------------------------

// The scan with the wall band 100..150 mm above the floor cut out: the
// refusal must name those heights, not the field names.
void wall_gap_message_gives_the_heights(void **) {
  pv::synth::PitSpec spec;
  spec.tilt_deg = 0;
  spec.yaw_deg = 0;
  spec.offset_mm[0] = spec.offset_mm[1] = spec.offset_mm[2] = 0;
  spec.stray_share = 0;
  spec.multipath_share = 0;
  spec.seed = 3;
  pv::synth::PitScan scan(spec);
  std::vector<pv_point_t> pts(150000);
  float zmin = INFINITY;
  for (pv_point_t &p : pts) {
    p = scan.next();
    zmin = std::fmin(zmin, p.z_mm);
  }
  std::string body;
  size_t n = 0;
  for (const pv_point_t &p : pts) {
    const float h = p.z_mm - zmin;
    if (h > 60.0f && h < 200.0f) continue;
    body.append(reinterpret_cast<const char *>(&p), sizeof p);
    ++n;
  }
  const std::string path = write_file(
      "gap.ply", "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                     "\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + body);
  const Run r = pitvol("measure " + quote(path));
  expect_exit(r, 4);
  expect_contains(r.err, "PV_ERR_WALL_GAP");
  const size_t at = r.err.find("the wall from ");
  assert_true(at != std::string::npos);
  double from = NAN, to = NAN;
  assert_int_equal(std::sscanf(r.err.c_str() + at, "the wall from %lf mm to %lf mm", &from, &to), 2);
  // The cut is 60..200 mm above the lowest point (nearly half the wall:
  // more than max_unseen_share of the volume); the band is reported in
  // sixteenths of the depth (18 mm here) that were under half seen.
  assert_true(from > 42.0 && from < 66.0);
  assert_true(to > 190.0 && to < 218.0);
}

// A closed sphere shell (radius 150 mm, points on a golden-angle spiral):
// refused as not a pit, and the refusal names the check (the mouth) with
// the figure it measured: a shell's rim section is a sliver of its widest.
void not_a_pit_names_the_check_and_its_figure(void **) {
  std::string body;
  const int n = 60000;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, rr = std::sqrt(1.0 - z * z);
    const double t = 2.39996322972865332 * i;
    const float p[3] = {float(150 * rr * std::cos(t)), float(150 * rr * std::sin(t)), float(150 * z)};
    body.append(reinterpret_cast<const char *>(p), sizeof p);
  }
  const std::string path = write_file(
      "sphere.ply", "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                        "\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + body);
  const Run r = pitvol("measure " + quote(path));
  expect_exit(r, 4);
  expect_contains(r.err, "PV_ERR_NOT_A_PIT");
  expect_contains(r.err, "PV_PIT_CHECK_NARROW_MOUTH");
  const size_t at = r.err.find("rim section / widest section ");
  assert_true(at != std::string::npos);
  double ratio = NAN, limit = NAN;
  assert_int_equal(std::sscanf(r.err.c_str() + at,
                               "rim section / widest section %lf (an open pit: at least %lf)",
                               &ratio, &limit), 2);
  assert_true(ratio >= 0 && ratio < limit);
  const Run j = pitvol("measure " + quote(path) + " --json");
  expect_exit(j, 4);
  expect_contains(j.out, "\"failed_check\": \"PV_PIT_CHECK_NARROW_MOUTH\"");
  expect_contains(j.out, "\"check_limit\": 0.5");
}

// The same pit twice, 3 mm apart along x (a scanner that lost its
// tracking): refused, with the check and its figure in the message.
void doubled_scan_names_the_check_and_its_figure(void **) {
  pv::synth::PitSpec spec;
  spec.seed = 11;
  pv::synth::PitScan a(spec), b(spec);
  const int n = 120000;
  std::string body;
  for (int copy = 0; copy < 2; ++copy) {
    for (int i = 0; i < n; ++i) {
      const pv_point_t q = copy == 0 ? a.next() : b.next();
      const float p[3] = {q.x_mm + (copy == 0 ? 0.0f : 3.0f), q.y_mm, q.z_mm};
      body.append(reinterpret_cast<const char *>(p), sizeof p);
    }
  }
  const std::string path = write_file(
      "doubled.ply", "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(2 * n) +
                         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + body);
  const Run r = pitvol("measure " + quote(path));
  expect_exit(r, 4);
  expect_contains(r.err, "PV_ERR_NOT_A_PIT");
  expect_contains(r.err, "PV_PIT_CHECK_DOUBLED_WALL");
  expect_contains(r.err, "scan the pit again in one steady pass");
  const size_t at = r.err.find("on two opposite sides: ");
  assert_true(at != std::string::npos);
  double contrast = NAN, limit = NAN;
  assert_int_equal(std::sscanf(r.err.c_str() + at,
                               "on two opposite sides: %lf %% more of the wall than across them (one scan: at "
                               "most %lf %%)",
                               &contrast, &limit), 2);
  assert_true(contrast > limit);
  const Run once = pitvol("measure " + quote(g_scan));  // the same pit, once
  expect_exit(once, 0);
}

int setup(void **) {
  char tmpl[] = "/tmp/pv_cli_hostile_XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return -1;
  g_dir = tmpl;
  g_scan = g_dir + "/pit.ply";
  pv::synth::PitSpec spec;
  spec.seed = 11;
  return pv::synth::write_scan_ply(g_scan.c_str(), spec, 120000) ? 0 : -1;
}

int teardown(void **) {
  const std::string cmd = "rm -rf " + quote(g_dir);
  return std::system(cmd.c_str()) == 0 ? 0 : -1;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: test_cli_hostile DIR_OF_TOOLS\n");
    return 2;
  }
  g_tools = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(config_dev_zero_is_refused_quickly),
      cmocka_unit_test(config_directory_is_refused),
      cmocka_unit_test(config_nul_byte_is_refused),
      cmocka_unit_test(config_long_line_is_refused),
      cmocka_unit_test(config_absurd_capacities_refused_at_validation),
      cmocka_unit_test(config_out_of_range_names_the_value),
      cmocka_unit_test(config_missing_file_says_why),
      cmocka_unit_test(unknown_short_option_is_a_usage_error),
      cmocka_unit_test(file_named_like_an_option_after_double_dash),
      cmocka_unit_test(layers_to_unwritable_path_fails_before_measuring),
      cmocka_unit_test(layers_to_full_disk_exits_non_zero),
      cmocka_unit_test(help_on_every_command_of_every_tool),
      cmocka_unit_test(argument_errors_of_every_tool_are_one_line),
      cmocka_unit_test(wall_gap_message_gives_the_heights),
      cmocka_unit_test(not_a_pit_names_the_check_and_its_figure),
      cmocka_unit_test(doubled_scan_names_the_check_and_its_figure),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
