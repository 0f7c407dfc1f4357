// Unit tests of the scan file readers: real files in a temp directory,
// read back in small chunks (cap = 7) and compared exactly.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pv_cmocka.h"
#include "scanio/scan_reader.h"

using pv::scanio::Error;
using pv::scanio::Format;
using pv::scanio::ScanReader;

namespace {

std::string g_dir;
std::vector<std::string> g_files;

int group_setup(void **) {
  const char *tmp = std::getenv("TMPDIR");
  std::string tmpl = std::string(tmp && *tmp ? tmp : "/tmp") + "/pv_scanio_XXXXXX";
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) return -1;
  g_dir = buf.data();
  return 0;
}

// Called from main() after the run: cmocka skips a group teardown when a
// test failed, and the temp dir must go in every case.
void cleanup() {
  for (const auto &f : g_files) std::remove(f.c_str());
  if (!g_dir.empty()) rmdir(g_dir.c_str());
}

std::string write_file(const std::string &name, const std::string &bytes) {
  std::string path = g_dir + "/" + name;
  FILE *f = std::fopen(path.c_str(), "wb");
  assert_non_null(f);
  assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::fclose(f);
  g_files.push_back(path);
  return path;
}

void expect_contains(const std::string &text, const char *sub) {
  if (text.find(sub) == std::string::npos) {
    print_error("expected '%s' in message: %s\n", sub, text.c_str());
    fail();
  }
}

// The known points: fractional, negative, large and small magnitudes.
std::vector<pv_point_t> known_points(size_t n = 40) {
  std::vector<pv_point_t> p(n);
  for (size_t i = 0; i < n; ++i) {
    float t = static_cast<float>(i);
    p[i].x_mm = t * 1.25f - 30.5f;
    p[i].y_mm = -1234.5678f + t * 0.1f;
    p[i].z_mm = (i % 2 ? -1.0f : 1.0f) * (0.001f + t * t * 17.3f);
  }
  return p;
}

// Integral points (for integer-typed coordinates).
std::vector<pv_point_t> int_points(size_t n = 30) {
  std::vector<pv_point_t> p(n);
  for (size_t i = 0; i < n; ++i) {
    int k = static_cast<int>(i);
    p[i] = {static_cast<float>(k * 3 - 40), static_cast<float>(100 - k),
            static_cast<float>(k * k)};
  }
  return p;
}

std::string fmt_float(float f) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", static_cast<double>(f));
  return b;
}

// Reads everything with the given cap; asserts no error.
std::vector<pv_point_t> read_all(const std::string &path, Format fmt, size_t cap,
                                 Format expect_fmt) {
  Error err;
  auto r = pv::scanio::open_scan(path, fmt, &err);
  if (!r) {
    print_error("open_scan(%s): %s\n", path.c_str(), err.message.c_str());
    fail();
  }
  assert_int_equal(static_cast<int>(r->format()), static_cast<int>(expect_fmt));
  std::vector<pv_point_t> out;
  std::vector<pv_point_t> buf(cap);
  for (;;) {
    long n = r->read(buf.data(), cap, &err);
    if (n < 0) {
      print_error("read(%s): %s (line %llu, byte %llu)\n", path.c_str(),
                  err.message.c_str(), static_cast<unsigned long long>(err.line),
                  static_cast<unsigned long long>(err.byte_offset));
      fail();
    }
    if (n == 0) break;
    assert_true(static_cast<size_t>(n) <= cap);
    out.insert(out.end(), buf.begin(), buf.begin() + n);
  }
  // End is sticky.
  assert_int_equal(r->read(buf.data(), cap, &err), 0);
  assert_int_equal(r->bytes_consumed(), r->bytes_total());
  return out;
}

bool same_float(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_points(const std::vector<pv_point_t> &got, const std::vector<pv_point_t> &want) {
  assert_int_equal(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) {
    if (!same_float(got[i].x_mm, want[i].x_mm) || !same_float(got[i].y_mm, want[i].y_mm) ||
        !same_float(got[i].z_mm, want[i].z_mm)) {
      print_error("point %zu: got (%.9g %.9g %.9g) want (%.9g %.9g %.9g)\n", i,
                  double(got[i].x_mm), double(got[i].y_mm), double(got[i].z_mm),
                  double(want[i].x_mm), double(want[i].y_mm), double(want[i].z_mm));
      fail();
    }
  }
}

// Expects open to succeed and a later read() to fail; returns the error.
Error read_error(const std::string &path, Format fmt = Format::Auto, size_t cap = 7) {
  Error err;
  auto r = pv::scanio::open_scan(path, fmt, &err);
  if (!r) {
    print_error("open_scan(%s) failed early: %s\n", path.c_str(), err.message.c_str());
    fail();
  }
  std::vector<pv_point_t> buf(cap);
  long n;
  while ((n = r->read(buf.data(), cap, &err)) > 0) {
  }
  assert_int_equal(n, -1);
  assert_false(err.message.empty());
  // Errors are sticky.
  Error again;
  assert_int_equal(r->read(buf.data(), cap, &again), -1);
  assert_string_equal(again.message.c_str(), err.message.c_str());
  return err;
}

Error open_error(const std::string &path, Format fmt = Format::Auto) {
  Error err;
  auto r = pv::scanio::open_scan(path, fmt, &err);
  assert_null(r.get());
  assert_false(err.message.empty());
  return err;
}

// ---- binary writer --------------------------------------------------------
struct Bin {
  bool be = false;
  std::string data;
  void raw(const void *p, size_t n) {
    const unsigned char *b = static_cast<const unsigned char *>(p);
    if (be)
      for (size_t i = n; i-- > 0;) data += static_cast<char>(b[i]);
    else
      for (size_t i = 0; i < n; ++i) data += static_cast<char>(b[i]);
  }
  // t: f float32, d float64, B uint8, b int8, h int16, H uint16, i int32, I uint32
  void put(char t, double v) {
    switch (t) {
      case 'f': { float x = static_cast<float>(v); raw(&x, 4); break; }
      case 'd': { raw(&v, 8); break; }
      case 'B': { uint8_t x = static_cast<uint8_t>(v); raw(&x, 1); break; }
      case 'b': { int8_t x = static_cast<int8_t>(v); raw(&x, 1); break; }
      case 'h': { int16_t x = static_cast<int16_t>(v); raw(&x, 2); break; }
      case 'H': { uint16_t x = static_cast<uint16_t>(v); raw(&x, 2); break; }
      case 'i': { int32_t x = static_cast<int32_t>(v); raw(&x, 4); break; }
      case 'I': { uint32_t x = static_cast<uint32_t>(v); raw(&x, 4); break; }
      default: fail();
    }
  }
};

// ---- PLY -------------------------------------------------------------------
// Vertex layout used by most PLY tests: extra properties around x, y, z.
const char *kVertexProps =
    "property float nx\n"
    "property %s x\n"
    "property uchar red\n"
    "property %s y\n"
    "property short intensity\n"
    "property %s z\n"
    "property float confidence\n";

std::string vertex_header(const char *type) {
  char b[512];
  std::snprintf(b, sizeof b, kVertexProps, type, type, type);
  return b;
}

std::string ply_binary(bool be, const char *type, char tc,
                       const std::vector<pv_point_t> &pts, bool face_after,
                       bool list_before) {
  std::string h = std::string("ply\nformat ") +
                  (be ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" +
                  "comment written by test_scanio\nobj_info nothing\n";
  if (list_before)
    h += "element camera 3\nproperty list uchar int ids\nproperty float f\n"
         "property list ushort double w\n";
  h += "element vertex " + std::to_string(pts.size()) + "\n" + vertex_header(type);
  if (face_after) h += "element face 2\nproperty list uchar int vertex_indices\n";
  h += "end_header\n";
  Bin b;
  b.be = be;
  if (list_before)
    for (int c = 0; c < 3; ++c) {
      b.put('B', c);  // list of c ints
      for (int k = 0; k < c; ++k) b.put('i', k * 1000);
      b.put('f', 0.5 * c);
      b.put('H', c + 1);  // list of c+1 doubles
      for (int k = 0; k <= c; ++k) b.put('d', k * 1e10);
    }
  for (size_t i = 0; i < pts.size(); ++i) {
    b.put('f', 0.25);
    b.put(tc, pts[i].x_mm);
    b.put('B', static_cast<double>(i % 256));
    b.put(tc, pts[i].y_mm);
    b.put('h', -7);
    b.put(tc, pts[i].z_mm);
    b.put('f', 1e30);
  }
  if (face_after)
    for (int f = 0; f < 2; ++f) {
      b.put('B', 3);
      for (int k = 0; k < 3; ++k) b.put('i', k);
    }
  return h + b.data;
}

void test_ply_binary_variants(void **) {
  auto pts = known_points();
  auto ipts = int_points();
  struct V { bool be; const char *type; char tc; bool ints; } vs[] = {
      {false, "float", 'f', false},  {true, "float", 'f', false},
      {false, "double", 'd', false}, {true, "double", 'd', false},
      {false, "float32", 'f', false}, {true, "float64", 'd', false},
      {false, "int", 'i', true},     {true, "short", 'h', true},
      {false, "int16", 'h', true},   {true, "uint32", 'I', true}};
  int k = 0;
  for (const V &v : vs) {
    const auto &want = v.ints ? ipts : pts;
    std::vector<pv_point_t> use = want;
    if (v.tc == 'I')  // unsigned: non-negative integral values
      for (auto &p : use) p = {std::fabs(p.x_mm), std::fabs(p.y_mm), std::fabs(p.z_mm)};
    for (int variant = 0; variant < 4; ++variant) {
      bool face = variant & 1, list = variant & 2;
      std::string path = write_file("bin" + std::to_string(k++) + ".ply",
                                    ply_binary(v.be, v.type, v.tc, use, face, list));
      expect_points(read_all(path, Format::Auto, 7, Format::Ply), use);
    }
  }
}

void test_ply_declared_points(void **) {
  auto pts = known_points(23);
  std::string path = write_file("decl.ply", ply_binary(false, "float", 'f', pts, true, true));
  Error err;
  auto r = pv::scanio::open_scan(path, Format::Ply, &err);
  assert_non_null(r.get());
  assert_int_equal(r->declared_points(), 23);
  assert_true(r->bytes_total() > 0);
  assert_true(r->bytes_consumed() < r->bytes_total());
}

std::string ply_ascii(const std::vector<pv_point_t> &pts, bool crlf, bool list_before,
                      bool face_after) {
  std::string nl = crlf ? "\r\n" : "\n";
  std::string h = "ply" + nl + "format ascii 1.0" + nl + "comment ascii test" + nl;
  if (list_before)
    h += "element material 2" + nl + "property list uchar float coeffs" + nl +
         "property int id" + nl;
  h += "element vertex " + std::to_string(pts.size()) + nl;
  std::string vh = vertex_header("float");
  // vertex also carries a list property
  vh += "property list uchar int tags\n";
  if (crlf) {
    std::string t;
    for (char c : vh) t += c == '\n' ? std::string("\r\n") : std::string(1, c);
    vh = t;
  }
  h += vh;
  if (face_after) h += "element face 1" + nl + "property list uchar int vertex_indices" + nl;
  h += "end_header" + nl;
  std::string d;
  if (list_before) d += "3 0.5 1e3 -2 7" + nl + "0 8" + nl;
  for (size_t i = 0; i < pts.size(); ++i) {
    d += "0.25 " + fmt_float(pts[i].x_mm) + " 200 " + fmt_float(pts[i].y_mm) + " -7 " +
         fmt_float(pts[i].z_mm) + " 1e30 " + std::to_string(i % 3);
    for (size_t k = 0; k < i % 3; ++k) d += " " + std::to_string(k);
    d += nl;
  }
  if (face_after) d += "3 0 1 2" + nl;
  return h + d;
}

void test_ply_ascii_variants(void **) {
  auto pts = known_points();
  int k = 0;
  for (int variant = 0; variant < 8; ++variant) {
    std::string path = write_file("asc" + std::to_string(k++) + ".PLY",
                                  ply_ascii(pts, variant & 1, variant & 2, variant & 4));
    expect_points(read_all(path, Format::Auto, 7, Format::Ply), pts);
  }
}

void test_ply_truncated_binary(void **) {
  std::vector<pv_point_t> pts(1234, pv_point_t{1.0f, 2.0f, 3.0f});
  std::string full = ply_binary(false, "float", 'f', pts, false, false);
  // Claim 5000 vertices, and cut the last record in half.
  std::string bytes = full;
  size_t pos = bytes.find("element vertex 1234");
  bytes.replace(pos, 19, "element vertex 5000");
  size_t header = bytes.find("end_header\n") + 11;
  bytes += std::string(10, '\0');  // a partial 1235th record (record = 23 bytes)
  std::string path = write_file("trunc.ply", bytes);
  Error err = read_error(path);
  expect_contains(err.message, "file ends after 1234 of 5000 vertices declared");
  expect_contains(err.message, "byte");
  assert_int_equal(err.byte_offset, header + 1234 * 23);
  expect_contains(err.message, std::to_string(header + 1234 * 23).c_str());
}

void test_ply_truncated_ascii(void **) {
  auto pts = known_points(10);
  std::string s = ply_ascii(pts, false, false, false);
  size_t pos = s.find("element vertex 10");
  s.replace(pos, 17, "element vertex 12");
  Error err = read_error(write_file("trunc_ascii.ply", s));
  expect_contains(err.message, "file ends after 10 of 12 vertices declared");
}

void test_ply_too_many_vertices(void **) {
  auto pts = known_points(10);
  std::string s = ply_ascii(pts, false, false, false);
  size_t pos = s.find("element vertex 10");
  s.replace(pos, 17, "element vertex 9");
  Error err = read_error(write_file("extra_ascii.ply", s));
  expect_contains(err.message, "data continues after the 9 vertices declared");
  assert_int_equal(err.line, 13 + 10);  // 13 header lines, then the 10th vertex
}

void test_ply_missing_z(void **) {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float w\nend_header\n1 2 3\n";
  Error err = open_error(write_file("noz.ply", s));
  expect_contains(err.message, "no 'z' property");
}

void test_ply_bad_token(void **) {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n4 five 6\n7 8 9\n";
  Error err = read_error(write_file("badtok.ply", s));
  assert_int_equal(err.line, 9);
  expect_contains(err.message, "line 9");
  expect_contains(err.message, "'five' is not a number");
  // Too few values on a line.
  s = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n4 5\n";
  err = read_error(write_file("fewvals.ply", s));
  assert_int_equal(err.line, 9);
  expect_contains(err.message, "too few values");
}

void test_ply_bad_headers(void **) {
  struct C { const char *text; const char *msg; } cs[] = {
      {"plx\nformat ascii 1.0\nend_header\n", "not a PLY file"},
      {"ply\nformat ascii 2.0\nelement vertex 0\nend_header\n", "version"},
      {"ply\nformat ebcdic 1.0\nend_header\n", "unknown PLY format"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "end_header"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", "known type"},
      {"ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "element <name> <count>"},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int v\nend_header\n",
       "no 'vertex' element"},
      {"ply\nelement vertex 1\nproperty float x\nend_header\n", "no 'format' line"},
      {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "before any 'element'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n"
       "property float y\nproperty float z\nend_header\n", "is a list"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty list float float f\n"
       "end_header\n", "list count type"},
      {"ply\nformat ascii 1.0\nbogus\nend_header\n", "unexpected header line"},
  };
  int k = 0;
  for (const C &c : cs) {
    Error err = open_error(write_file("hdr" + std::to_string(k++) + ".ply", c.text));
    expect_contains(err.message, c.msg);
    assert_true(err.line >= 1);
  }
}

void test_ply_binary_with_list_in_vertex(void **) {
  auto pts = known_points(17);
  std::string h = "ply\nformat binary_big_endian 1.0\nelement vertex 17\n"
                  "property list uchar float feat\nproperty double z\nproperty double y\n"
                  "property double x\nproperty list int uchar tags\nend_header\n";
  Bin b;
  b.be = true;
  for (size_t i = 0; i < pts.size(); ++i) {
    b.put('B', static_cast<double>(i % 4));
    for (size_t k = 0; k < i % 4; ++k) b.put('f', 1.5);
    b.put('d', pts[i].z_mm);
    b.put('d', pts[i].y_mm);
    b.put('d', pts[i].x_mm);
    b.put('i', 2);
    b.put('B', 1);
    b.put('B', 2);
  }
  std::string path = write_file("vlist.ply", h + b.data);
  expect_points(read_all(path, Format::Ply, 7, Format::Ply), pts);
  // Same file cut inside a list: a clear truncation error.
  std::string cut = h + b.data.substr(0, b.data.size() - 1);
  Error err = read_error(write_file("vlist_cut.ply", cut));
  expect_contains(err.message, "file ends after 16 of 17 vertices declared");
}

void test_ply_trailing_garbage_binary(void **) {
  auto pts = known_points(5);
  std::string ok = ply_binary(false, "float", 'f', pts, false, false) + "\n";
  expect_points(read_all(write_file("tail_ok.ply", ok), Format::Auto, 7, Format::Ply), pts);
  std::string bad = ply_binary(false, "float", 'f', pts, false, false) + "0123456789";
  Error err = read_error(write_file("tail_bad.ply", bad));
  expect_contains(err.message, "data continues after the 5 vertices declared");
}

// ---- text ------------------------------------------------------------------
void test_xyz_spaces(void **) {
  auto pts = known_points();
  std::string s;
  for (size_t i = 0; i < pts.size(); ++i) {
    s += (i % 2 ? "  " : "") + fmt_float(pts[i].x_mm) + (i % 3 ? "\t" : "   ") +
         fmt_float(pts[i].y_mm) + " " + fmt_float(pts[i].z_mm);
    if (i % 4 == 1) s += " 255 128 0 0.5";  // extra columns
    s += "\n";
    if (i % 5 == 0) s += "\n   \n";            // blank lines
  }
  s.pop_back();  // last line without a newline
  expect_points(read_all(write_file("a.xyz", s), Format::Auto, 7, Format::Xyz), pts);
  expect_points(read_all(write_file("a.asc", s), Format::Auto, 7, Format::Xyz), pts);
  expect_points(read_all(write_file("a.TXT", s), Format::Auto, 7, Format::Xyz), pts);
  expect_points(read_all(write_file("a.dat", s), Format::Xyz, 7, Format::Xyz), pts);
}

void test_csv_header_semicolons_comments_crlf(void **) {
  auto pts = known_points();
  std::string csv = "# exported by a scanner\r\n// second comment\r\nx,y,z,intensity\r\n";
  std::string semi = "X;Y;Z;R;G;B\n";
  for (size_t i = 0; i < pts.size(); ++i) {
    csv += fmt_float(pts[i].x_mm) + "," + fmt_float(pts[i].y_mm) + ", " +
           fmt_float(pts[i].z_mm) + ",0.75\r\n";
    semi += fmt_float(pts[i].x_mm) + ";" + fmt_float(pts[i].y_mm) + ";" +
            fmt_float(pts[i].z_mm) + ";1;2;3\n";
    if (i == 10) {
      csv += "# a comment in the middle\r\n\r\n";
      semi += "  // indented comment\n";
    }
  }
  expect_points(read_all(write_file("h.csv", csv), Format::Auto, 7, Format::Csv), pts);
  expect_points(read_all(write_file("s.csv", semi), Format::Auto, 7, Format::Csv), pts);
  // Special values and signs.
  std::string sp = "+1.5 -2e3 .5\nnan inf -inf\n1E-50 1e50 -0\n";
  auto got = read_all(write_file("special.xyz", sp), Format::Auto, 7, Format::Xyz);
  assert_int_equal(got.size(), 3);
  assert_true(got[0].x_mm == 1.5f && got[0].y_mm == -2000.0f && got[0].z_mm == 0.5f);
  assert_true(std::isnan(got[1].x_mm) && std::isinf(got[1].y_mm) && got[1].z_mm < 0);
  assert_true(got[2].x_mm >= 0.0f && got[2].x_mm < 1e-37f && std::isinf(got[2].y_mm));
}

void test_xyz_garbage_line5(void **) {
  std::string s = "1 2 3\n4 5 6\n7 8 9\n10 11 12\n13 oops 15\n16 17 18\n";
  Error err = read_error(write_file("garbage.xyz", s));
  assert_int_equal(err.line, 5);
  expect_contains(err.message, "line 5");
  expect_contains(err.message, "'oops'");
  expect_contains(err.message, "column 2");
  // A non-numeric line after the data started is an error, not a header.
  s = "x y z\n1 2 3\n4 5 6\n# fine\nX Y Z\n";
  err = read_error(write_file("late_header.xyz", s));
  assert_int_equal(err.line, 5);
  expect_contains(err.message, "'X'");
}

void test_xyz_bad_numbers(void **) {
  Error err = read_error(write_file("dots.xyz", "1 2 3\n1.2.3 4 5\n"));
  assert_int_equal(err.line, 2);
  expect_contains(err.message, "'1.2.3' is not a number");
  err = read_error(write_file("two.xyz", "1 2 3\n4 5\n"));
  assert_int_equal(err.line, 2);
  expect_contains(err.message, "only 2 number(s)");
  err = read_error(write_file("trail.csv", "1,2,3\n1,2,3abc\n"));
  expect_contains(err.message, "'3abc'");
  err = read_error(write_file("hex.xyz", "0x10 1 2\n"));  // first line: header?
  expect_contains(err.message, "no points found");
  // Offending text is truncated in the message.
  err = read_error(write_file("longbad.xyz", "1 2 3\n4 5 6\n" + std::string(500, 'q') + "\n"));
  assert_true(err.message.size() < 300);
  expect_contains(err.message, "...");
}

void test_xyz_long_line(void **) {
  std::string s = "1 2 3\n" + std::string(200000, '7') + "\n4 5 6\n";
  Error err = read_error(write_file("long.xyz", s));
  assert_int_equal(err.line, 2);
  expect_contains(err.message, "longer than");
}

void test_text_only_header(void **) {
  Error err = read_error(write_file("hdronly.csv", "x,y,z\n# nothing\n"));
  expect_contains(err.message, "no points found");
  std::string many;
  for (int i = 0; i < 150; ++i) many += "not data\n";
  err = read_error(write_file("notdata.txt", many));
  expect_contains(err.message, "is this really a text point file");
}

// ---- PCD -------------------------------------------------------------------
void test_pcd_ascii(void **) {
  auto pts = known_points();
  pts[3].y_mm = NAN;  // NaN points pass through
  for (const char *ver : {"0.7", ".6"}) {
    std::string s = std::string("# .PCD v") + ver + " - Point Cloud Data file format\n" +
                    "VERSION " + ver + "\n"
                    "FIELDS intensity x y z normal rgb\n"
                    "SIZE 4 4 4 4 4 4\nTYPE F F F F F U\nCOUNT 1 1 1 1 3 1\n"
                    "WIDTH " + std::to_string(pts.size()) + "\nHEIGHT 1\n"
                    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(pts.size()) +
                    "\nDATA ascii\n";
    for (const auto &p : pts)
      s += "0.5 " + fmt_float(p.x_mm) + " " + (std::isnan(p.y_mm) ? "nan" : fmt_float(p.y_mm)) +
           " " + fmt_float(p.z_mm) + " 0 0 1 4278190080\n";
    std::string path = write_file(std::string("a") + ver + ".pcd", s);
    expect_points(read_all(path, Format::Auto, 7, Format::Pcd), pts);
  }
}

std::string pcd_binary(const std::vector<pv_point_t> &pts, bool dbl, uint64_t declared) {
  std::string s = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
                  "FIELDS rgb x y z _ normal_x curvature\n";
  s += dbl ? "SIZE 4 8 8 8 1 4 4\nTYPE U F F F U F F\n" : "SIZE 4 4 4 4 1 4 4\nTYPE U F F F U F F\n";
  s += "COUNT 1 1 1 1 3 2 1\nWIDTH " + std::to_string(declared) + "\nHEIGHT 1\n"
       "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(declared) + "\nDATA binary\n";
  Bin b;
  for (const auto &p : pts) {
    b.put('I', 0xff00ff);
    b.put(dbl ? 'd' : 'f', p.x_mm);
    b.put(dbl ? 'd' : 'f', p.y_mm);
    b.put(dbl ? 'd' : 'f', p.z_mm);
    for (int k = 0; k < 3; ++k) b.put('B', 0);
    b.put('f', 0.1);
    b.put('f', 0.2);
    b.put('f', 0.3);
  }
  return s + b.data;
}

void test_pcd_binary(void **) {
  auto pts = known_points();
  pts[5].x_mm = pts[5].y_mm = pts[5].z_mm = NAN;
  expect_points(read_all(write_file("b4.pcd", pcd_binary(pts, false, pts.size())),
                         Format::Auto, 7, Format::Pcd), pts);
  expect_points(read_all(write_file("b8.pcd", pcd_binary(pts, true, pts.size())),
                         Format::Pcd, 7, Format::Pcd), pts);
  Error err = read_error(write_file("bt.pcd", pcd_binary(pts, false, pts.size() + 3)));
  expect_contains(err.message, "file ends after 40 of 43 points declared");
  assert_true(err.byte_offset > 0);
}

void test_pcd_errors(void **) {
  std::string base = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                     "WIDTH 1\nHEIGHT 1\nPOINTS 1\n";
  Error err = open_error(write_file("c.pcd", base + "DATA binary_compressed\n\x01\x02"));
  expect_contains(err.message, "binary_compressed is not supported");
  expect_contains(err.message, "pcl_convert_pcd_ascii_binary");
  err = open_error(write_file("noz.pcd", "VERSION 0.7\nFIELDS x y w\nSIZE 4 4 4\nTYPE F F F\n"
                                        "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n"));
  expect_contains(err.message, "no field 'z'");
  err = open_error(write_file("sz.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\n"
                                       "POINTS 1\nDATA ascii\n1 2 3\n"));
  expect_contains(err.message, "SIZE");
  err = open_error(write_file("f2.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 2\nTYPE F F F\n"
                                       "POINTS 1\nDATA ascii\n1 2 3\n"));
  expect_contains(err.message, "only 4 or 8");
  err = open_error(write_file("nodata.pcd", base));
  expect_contains(err.message, "no 'DATA' line");
  err = read_error(write_file("badtok.pcd", base + "DATA ascii\n1 x 3\n"));
  assert_int_equal(err.line, 10);
  expect_contains(err.message, "'x' is not a number");
  err = read_error(write_file("few.pcd", base + "DATA ascii\n1 2\n"));
  expect_contains(err.message, "2 values, the header's fields need 3");
}

// ---- misc ------------------------------------------------------------------
void test_open_errors(void **) {
  Error err = open_error(write_file("empty.ply", ""));
  expect_contains(err.message, "is empty (0 bytes)");
  err = open_error(write_file("empty.xyz", ""));
  expect_contains(err.message, "is empty");
  err = open_error(g_dir + "/does_not_exist.ply");
  expect_contains(err.message, "cannot open");
  err = open_error(write_file("scan.bin", "1 2 3\n"));
  expect_contains(err.message, "cannot tell the format");
  err = open_error(write_file("noext", "1 2 3\n"));
  expect_contains(err.message, "cannot tell the format");
  err = open_error(g_dir + "/.ply");
  err = open_error(g_dir);
  expect_contains(err.message, "cannot tell the format");
  err = open_error(g_dir, Format::Ply);
  expect_contains(err.message, "is a directory");
  // A NULL err is allowed.
  assert_null(pv::scanio::open_scan(g_dir + "/nope.ply", Format::Auto, nullptr).get());
  // cap == 0 is an error, so that 0 always means the end.
  auto r = pv::scanio::open_scan(write_file("one.xyz", "1 2 3\n"), Format::Auto, &err);
  assert_non_null(r.get());
  pv_point_t p;
  assert_int_equal(r->read(&p, 0, &err), -1);
}

void test_format_names(void **) {
  using pv::scanio::format_from_name;
  assert_true(format_from_name("ply") == Format::Ply);
  assert_true(format_from_name("PLY") == Format::Ply);
  assert_true(format_from_name("xyz") == Format::Xyz);
  assert_true(format_from_name("asc") == Format::Xyz);
  assert_true(format_from_name("txt") == Format::Xyz);
  assert_true(format_from_name("csv") == Format::Csv);
  assert_true(format_from_name("Pcd") == Format::Pcd);
  assert_true(format_from_name("dir.d/scan.Ply") == Format::Ply);
  assert_true(format_from_name("las") == Format::Auto);
  assert_true(format_from_name("") == Format::Auto);
  assert_string_equal(pv::scanio::format_name(Format::Ply), "ply");
  assert_string_equal(pv::scanio::format_name(Format::Auto), "auto");
  assert_string_equal(pv::scanio::format_name(Format::Csv), "csv");
  assert_string_equal(pv::scanio::format_name(Format::Pcd), "pcd");
  assert_string_equal(pv::scanio::format_name(Format::Xyz), "xyz");
}

// One million points, binary PLY, read in chunks of 65536: streaming.
void test_ply_million(void **) {
  const uint32_t n = 1000000;
  std::string path = g_dir + "/million.ply";
  g_files.push_back(path);
  FILE *f = std::fopen(path.c_str(), "wb");
  assert_non_null(f);
  std::fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %u\n"
                  "property float x\nproperty float y\nproperty float z\n"
                  "property uchar red\nend_header\n", n);
  std::vector<unsigned char> rec(13);
  for (uint32_t i = 0; i < n; ++i) {
    float v[3] = {static_cast<float>(i), static_cast<float>(i) * 0.5f, -static_cast<float>(i % 1000)};
    std::memcpy(rec.data(), v, 12);  // host is little endian (x86/arm)
    rec[12] = static_cast<unsigned char>(i);
    std::fwrite(rec.data(), 1, rec.size(), f);
  }
  std::fclose(f);
  Error err;
  auto r = pv::scanio::open_scan(path, Format::Auto, &err);
  assert_non_null(r.get());
  assert_int_equal(r->declared_points(), n);
  std::vector<pv_point_t> buf(65536);
  uint64_t total = 0;
  long got;
  uint64_t last_consumed = 0;
  while ((got = r->read(buf.data(), buf.size(), &err)) > 0) {
    for (long k = 0; k < got; k += 4099) {
      uint64_t i = total + static_cast<uint64_t>(k);
      assert_true(buf[k].x_mm == static_cast<float>(i));
      assert_true(buf[k].z_mm == -static_cast<float>(i % 1000));
    }
    total += static_cast<uint64_t>(got);
    assert_true(r->bytes_consumed() > last_consumed);
    last_consumed = r->bytes_consumed();
  }
  assert_int_equal(got, 0);
  assert_int_equal(total, n);
  assert_int_equal(r->bytes_consumed(), r->bytes_total());
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ply_binary_variants),
      cmocka_unit_test(test_ply_declared_points),
      cmocka_unit_test(test_ply_ascii_variants),
      cmocka_unit_test(test_ply_truncated_binary),
      cmocka_unit_test(test_ply_truncated_ascii),
      cmocka_unit_test(test_ply_too_many_vertices),
      cmocka_unit_test(test_ply_missing_z),
      cmocka_unit_test(test_ply_bad_token),
      cmocka_unit_test(test_ply_bad_headers),
      cmocka_unit_test(test_ply_binary_with_list_in_vertex),
      cmocka_unit_test(test_ply_trailing_garbage_binary),
      cmocka_unit_test(test_xyz_spaces),
      cmocka_unit_test(test_csv_header_semicolons_comments_crlf),
      cmocka_unit_test(test_xyz_garbage_line5),
      cmocka_unit_test(test_xyz_bad_numbers),
      cmocka_unit_test(test_xyz_long_line),
      cmocka_unit_test(test_text_only_header),
      cmocka_unit_test(test_pcd_ascii),
      cmocka_unit_test(test_pcd_binary),
      cmocka_unit_test(test_pcd_errors),
      cmocka_unit_test(test_open_errors),
      cmocka_unit_test(test_format_names),
      cmocka_unit_test(test_ply_million),
  };
  int rc = cmocka_run_group_tests(tests, group_setup, nullptr);
  cleanup();
  return rc;
}
