// CLI replay over every input format (CTest label "corpus").
//
//   test_cli_formats PATH/TO/pitvol
//
// One synthetic scan (pv::synth::PitScan, fixed seed) is written by this
// test in every format the scan readers support, then `pitvol measure F
// --json` is run on each. Every format must give the same volume as the
// binary float PLY (text files are written with %.9g, so every float
// round-trips exactly and the volumes are bit-identical), and that volume
// must be within 1 % of the closed-form volume.
//
// Files in metres and centimetres: the reader rounds each file value to
// float and the CLI then scales it to mm and rounds to float again, so a
// coordinate may land one ulp away from the original mm float. The method
// is not continuous in single points (thinning and clustering keep or drop
// points), and such ulp-level moves shift this scan's volume by about
// 2.5e-4 relative. So the units files are compared with a binary float PLY
// of exactly the mm floats the CLI must produce from them (identical volume
// expected: this checks the scale), and with the original scan only within
// kUnitsRelTol.
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
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

constexpr size_t kPoints = 150000;
constexpr uint64_t kSeed = 7;
// Units files against the original mm scan (see the top comment).
constexpr double kUnitsRelTol = 1e-3;

std::string g_pitvol;
std::string g_dir;
std::vector<std::string> g_files;
std::vector<pv_point_t> g_pts;
pv::synth::PitSpec g_spec;
double g_ref_volume = NAN;  // binary little endian float PLY

// Runs `pitvol ARGS` through the shell; stdout via popen, stderr via a file.
Run run_pitvol(const std::string &args) {
  return run_command(quote(g_pitvol) + " " + args, g_dir + "/stderr.txt");
}

Run measure_json(const std::string &file, const std::string &extra = "") {
  return run_pitvol("measure " + quote(file) + " --json" + (extra.empty() ? "" : " " + extra));
}

// Tiny JSON lookups: the CLI writes `"key": value` on one line.
std::string json_string(const std::string &json, const char *key) {
  const std::string k = std::string("\"") + key + "\": \"";
  const size_t b = json.find(k);
  if (b == std::string::npos) return "";
  const size_t s = b + k.size();
  const size_t e = json.find('"', s);
  return e == std::string::npos ? "" : json.substr(s, e - s);
}

double json_number(const std::string &json, const char *key) {
  const std::string k = std::string("\"") + key + "\": ";
  const size_t b = json.find(k);
  if (b == std::string::npos) return NAN;
  const char *s = json.c_str() + b + k.size();
  char *end = nullptr;
  const double v = std::strtod(s, &end);
  return end == s ? NAN : v;
}

std::string json_warnings(const std::string &json) {
  const std::string k = "\"warnings\": [";
  const size_t b = json.find(k);
  if (b == std::string::npos) return "";
  const size_t e = json.find(']', b);
  return json.substr(b + k.size(), e == std::string::npos ? std::string::npos : e - b - k.size());
}

void expect_contains(const std::string &text, const std::string &sub) {
  if (text.find(sub) == std::string::npos) {
    print_error("expected '%s' in: %s\n", sub.c_str(), text.c_str());
    fail();
  }
}

// ---- writers ------------------------------------------------------------

std::string path_of(const std::string &name) {
  std::string p = g_dir + "/" + name;
  g_files.push_back(p);
  return p;
}

void put_be(std::string *o, const void *v, size_t n) {
  const unsigned char *b = static_cast<const unsigned char *>(v);
  for (size_t i = n; i > 0; --i) o->push_back(char(b[i - 1]));
}

void put_le(std::string *o, const void *v, size_t n) {
  o->append(static_cast<const char *>(v), n);
}

void write_bytes(const std::string &path, const std::string &bytes) {
  FILE *f = std::fopen(path.c_str(), "wb");
  assert_non_null(f);
  assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  assert_int_equal(std::fclose(f), 0);
}

std::string fmt3(const char *f, double a, double b, double c) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// Text line per point; scale converts mm to the file's unit.
std::string text_points(const char *line_fmt, double scale = 1.0) {
  std::string o;
  o.reserve(g_pts.size() * 40);
  for (const pv_point_t &p : g_pts) {
    o += fmt3(line_fmt, double(p.x_mm) * scale, double(p.y_mm) * scale, double(p.z_mm) * scale);
  }
  return o;
}

std::string ply_header(const char *format, const std::string &props, size_t n,
                       const std::string &after = "") {
  return std::string("ply\nformat ") + format + " 1.0\ncomment pitvol test_cli_formats\n" +
         "element vertex " + std::to_string(n) + "\n" + props + after + "end_header\n";
}

const char kFloatXyz[] = "property float x\nproperty float y\nproperty float z\n";

std::string ply_binary_le_float(const std::vector<pv_point_t> &pts) {
  std::string o = ply_header("binary_little_endian", kFloatXyz, pts.size());
  for (const pv_point_t &p : pts) {
    put_le(&o, &p.x_mm, 4);
    put_le(&o, &p.y_mm, 4);
    put_le(&o, &p.z_mm, 4);
  }
  return o;
}

std::string ply_ascii() {
  return ply_header("ascii", kFloatXyz, g_pts.size()) + text_points("%.9g %.9g %.9g\n");
}

// Big endian doubles among other properties, plus a face element after the
// vertices.
std::string ply_binary_be_double() {
  const std::string props =
      "property double x\nproperty double y\nproperty double z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  const std::string faces = "element face 2\nproperty list uchar int vertex_indices\n";
  std::string o = ply_header("binary_big_endian", props, g_pts.size(), faces);
  for (size_t i = 0; i < g_pts.size(); ++i) {
    const pv_point_t &p = g_pts[i];
    const double x = p.x_mm, y = p.y_mm, z = p.z_mm;
    const float nrm[3] = {0.0f, 0.6f, 0.8f};
    const unsigned char rgb[3] = {uint8_t(i), uint8_t(i >> 8), 200};
    put_be(&o, &x, 8);
    put_be(&o, &y, 8);
    put_be(&o, &z, 8);
    for (float v : nrm) put_be(&o, &v, 4);
    o.append(reinterpret_cast<const char *>(rgb), 3);
  }
  for (int32_t f = 0; f < 2; ++f) {
    o.push_back(3);
    for (int32_t k = 0; k < 3; ++k) {
      const int32_t idx = f * 3 + k;
      put_be(&o, &idx, 4);
    }
  }
  return o;
}

std::string pcd_header(const std::string &fields, const std::string &size,
                       const std::string &type, const std::string &count, const char *data) {
  const std::string n = std::to_string(g_pts.size());
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields +
         "\nSIZE " + size + "\nTYPE " + type + "\nCOUNT " + count + "\nWIDTH " + n +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " + data + "\n";
}

std::string pcd_ascii() {
  return pcd_header("x y z", "4 4 4", "F F F", "1 1 1", "ascii") + text_points("%.9g %.9g %.9g\n");
}

// Packed little endian records of 14 bytes: x y z float, intensity uint16.
std::string pcd_binary() {
  std::string o = pcd_header("x y z intensity", "4 4 4 2", "F F F U", "1 1 1 1", "binary");
  for (size_t i = 0; i < g_pts.size(); ++i) {
    const pv_point_t &p = g_pts[i];
    const uint16_t intensity = uint16_t(i * 37u);
    put_le(&o, &p.x_mm, 4);
    put_le(&o, &p.y_mm, 4);
    put_le(&o, &p.z_mm, 4);
    put_le(&o, &intensity, 2);
  }
  return o;
}

// ---- setup ---------------------------------------------------------------

int group_setup(void **) {
  const char *tmp = std::getenv("TMPDIR");
  std::string tmpl = std::string(tmp && *tmp ? tmp : "/tmp") + "/pv_cli_formats_XXXXXX";
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) return -1;
  g_dir = buf.data();
  g_spec.seed = kSeed;
  pv::synth::PitScan scan(g_spec);
  g_pts.resize(kPoints);
  for (pv_point_t &p : g_pts) p = scan.next();
  return 0;
}

int group_teardown(void **) {
  for (const auto &f : g_files) std::remove(f.c_str());
  rmdir(g_dir.c_str());
  return 0;
}

// Measures file and checks success; returns the volume.
double measure_ok(const std::string &file, const std::string &extra = "") {
  const Run r = measure_json(file, extra);
  if (r.exit_code != 0) print_error("pitvol exit %d\nstdout: %s\nstderr: %s\n", r.exit_code, r.out.c_str(), r.err.c_str());
  assert_int_equal(r.exit_code, 0);
  const std::string status = json_string(r.out, "status");
  if (status != "PV_OK") print_error("status '%s' in %s\n", status.c_str(), r.out.c_str());
  assert_true(status == "PV_OK");
  const double v = json_number(r.out, "volume_cm3");
  assert_true(std::isfinite(v));
  return v;
}

// The reference: binary float PLY, must be within 1 % of the exact volume.
double reference_volume() {
  if (std::isnan(g_ref_volume)) {
    const std::string f = path_of("ref_le_float.ply");
    write_bytes(f, ply_binary_le_float(g_pts));
    g_ref_volume = measure_ok(f);
    const double exact = pv::synth::exact_volume_cm3(g_spec);
    std::printf("reference (binary LE float PLY): %.6f cm3, exact %.6f cm3, %+.3f %%\n", g_ref_volume,
                exact, 100.0 * (g_ref_volume - exact) / exact);
  }
  return g_ref_volume;
}

void check_same_volume(const std::string &name, const std::string &bytes) {
  const double ref = reference_volume();
  const std::string f = path_of(name);
  write_bytes(f, bytes);
  const double v = measure_ok(f);
  std::remove(f.c_str());
  const double rel = std::fabs(v - ref) / ref;
  std::printf("%-22s %.6f cm3 (relative difference to reference %.3g)\n", name.c_str(), v, rel);
  // Same floats in every mm file: the same bits must come out (the 1e-6
  // bound is then met with room to spare).
  if (v != ref) print_error("%s: %.17g cm3 != reference %.17g cm3\n", name.c_str(), v, ref);
  assert_true(v == ref);
  const double exact = pv::synth::exact_volume_cm3(g_spec);
  assert_true(std::fabs(v - exact) / exact < 0.01);
}

// ---- format tests --------------------------------------------------------

void test_ply_binary_le_float(void **) {
  const double exact = pv::synth::exact_volume_cm3(g_spec);
  assert_true(std::fabs(reference_volume() - exact) / exact < 0.01);
}

void test_ply_ascii(void **) { check_same_volume("scan_ascii.ply", ply_ascii()); }

void test_ply_binary_be_double(void **) {
  check_same_volume("scan_be_double.ply", ply_binary_be_double());
}

void test_xyz(void **) { check_same_volume("scan.xyz", text_points("%.9g %.9g %.9g\n")); }

void test_csv(void **) { check_same_volume("scan.csv", "x,y,z\n" + text_points("%.9g,%.9g,%.9g\n")); }

void test_asc(void **) {
  // Tab separated, an extra intensity column ignored.
  check_same_volume("scan.asc", text_points("%.9g\t%.9g\t%.9g\t0.5\n"));
}

void test_pcd_ascii(void **) { check_same_volume("scan_ascii.pcd", pcd_ascii()); }

void test_pcd_binary(void **) { check_same_volume("scan_binary.pcd", pcd_binary()); }

// The scan written in another unit (file value = mm * to_file, %.9g), and
// the mm floats the CLI computes from it: float(float(text) * to_mm).
void check_units(const std::string &name, double to_file, const std::string &units, double to_mm) {
  const double ref = reference_volume();
  std::string text;
  std::vector<pv_point_t> as_mm(g_pts.size());
  for (size_t i = 0; i < g_pts.size(); ++i) {
    const pv_point_t &p = g_pts[i];
    const std::string line = fmt3("%.9g %.9g %.9g\n", double(p.x_mm) * to_file,
                                  double(p.y_mm) * to_file, double(p.z_mm) * to_file);
    text += line;
    char *c = const_cast<char *>(line.c_str());
    float *dst[3] = {&as_mm[i].x_mm, &as_mm[i].y_mm, &as_mm[i].z_mm};
    for (float *d : dst) {
      const float file_value = std::strtof(c, &c);
      *d = float(double(file_value) * to_mm);
    }
  }
  const std::string equiv = path_of(name + ".equivalent_mm.ply");
  write_bytes(equiv, ply_binary_le_float(as_mm));
  const double v_equiv = measure_ok(equiv);
  std::remove(equiv.c_str());

  const std::string f = path_of(name);
  write_bytes(f, text);
  const double v = measure_ok(f, "--units " + units);
  std::remove(f.c_str());
  const double rel = std::fabs(v - ref) / ref;
  std::printf("%-22s --units %-2s %.6f cm3 (same floats in mm: %.6f cm3; relative difference to "
              "reference %.3g)\n",
              name.c_str(), units.c_str(), v, v_equiv, rel);
  if (v != v_equiv) print_error("%s: %.17g cm3 != %.17g cm3 of the same mm floats\n", name.c_str(), v, v_equiv);
  assert_true(v == v_equiv);
  assert_true(rel <= kUnitsRelTol);
  const double exact = pv::synth::exact_volume_cm3(g_spec);
  assert_true(std::fabs(v - exact) / exact < 0.01);
}

void test_units_metres(void **) { check_units("scan_metres.xyz", 1e-3, "m", 1000.0); }

void test_units_centimetres(void **) { check_units("scan_centimetres.xyz", 1e-1, "cm", 10.0); }

// ---- error paths ---------------------------------------------------------

void test_truncated_binary_ply(void **) {
  std::string bytes = ply_binary_le_float(g_pts);
  const size_t header = bytes.find("end_header\n") + 11;
  bytes.resize(header + 1000 * 12 + 5);  // 1000 whole points and a partial one
  const std::string f = path_of("truncated.ply");
  write_bytes(f, bytes);
  const Run r = measure_json(f);
  std::printf("truncated PLY: exit %d, stderr: %s", r.exit_code, r.err.c_str());
  assert_int_equal(r.exit_code, 3);
  const bool names_where = r.err.find("byte") != std::string::npos ||
                           r.err.find(std::to_string(kPoints)) != std::string::npos;
  if (!names_where) print_error("no byte offset or vertex count in: %s\n", r.err.c_str());
  assert_true(names_where);
}

void test_xyz_garbage_line5(void **) {
  std::string text;
  for (size_t i = 0; i < 300; ++i) {
    const pv_point_t &p = g_pts[i];
    if (i == 4) text += "12.5 garbage 7.25\n";
    else text += fmt3("%.9g %.9g %.9g\n", p.x_mm, p.y_mm, p.z_mm);
  }
  const std::string f = path_of("garbage.xyz");
  write_bytes(f, text);
  const Run r = measure_json(f);
  std::printf("garbage XYZ: exit %d, stderr: %s", r.exit_code, r.err.c_str());
  assert_int_equal(r.exit_code, 3);
  const bool names_line = r.err.find(f + ":5:") != std::string::npos ||
                          r.err.find("line 5") != std::string::npos;
  if (!names_line) print_error("line 5 not named in: %s\n", r.err.c_str());
  assert_true(names_line);
}

void test_flat_plane(void **) {
  std::string text;
  for (int i = 0; i < 200; ++i) {
    text += fmt3("%.9g %.9g %.9g\n", (i % 20) * 10.0, (i / 20) * 10.0, 500.0);
  }
  const std::string f = path_of("plane.xyz");
  write_bytes(f, text);
  const Run r = measure_json(f);
  std::printf("flat plane: exit %d, status %s\n", r.exit_code, json_string(r.out, "status").c_str());
  assert_int_equal(r.exit_code, 4);
}

void test_missing_file(void **) {
  const Run r = measure_json(g_dir + "/does_not_exist.ply");
  assert_int_equal(r.exit_code, 3);
}

void test_no_file(void **) {
  const Run r = run_pitvol("measure");
  assert_int_equal(r.exit_code, 2);
}

void test_bad_units(void **) {
  const std::string f = path_of("units_ref.ply");
  write_bytes(f, ply_binary_le_float(std::vector<pv_point_t>(g_pts.begin(), g_pts.begin() + 2000)));
  const Run r = measure_json(f, "--units furlong");
  assert_int_equal(r.exit_code, 2);
}

void test_metres_read_as_mm(void **) {
  const std::string f = path_of("metres_as_mm.xyz");
  write_bytes(f, text_points("%.9g %.9g %.9g\n", 1e-3));
  const Run r = measure_json(f);
  const std::string w = json_warnings(r.out);
  std::printf("metres read as mm: exit %d, warnings [%s]\n", r.exit_code, w.c_str());
  expect_contains(w, "metres");
  std::remove(f.c_str());
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: test_cli_formats PATH/TO/pitvol\n");
    return 2;
  }
  g_pitvol = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ply_binary_le_float),
      cmocka_unit_test(test_ply_ascii),
      cmocka_unit_test(test_ply_binary_be_double),
      cmocka_unit_test(test_xyz),
      cmocka_unit_test(test_csv),
      cmocka_unit_test(test_asc),
      cmocka_unit_test(test_pcd_ascii),
      cmocka_unit_test(test_pcd_binary),
      cmocka_unit_test(test_units_metres),
      cmocka_unit_test(test_units_centimetres),
      cmocka_unit_test(test_truncated_binary_ply),
      cmocka_unit_test(test_xyz_garbage_line5),
      cmocka_unit_test(test_flat_plane),
      cmocka_unit_test(test_missing_file),
      cmocka_unit_test(test_no_file),
      cmocka_unit_test(test_bad_units),
      cmocka_unit_test(test_metres_read_as_mm),
  };
  return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
