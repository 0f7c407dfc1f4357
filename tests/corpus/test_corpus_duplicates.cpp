// A scanner that resends frames must not move the volume: a resent frame
// would otherwise weigh its part of the wall twice.
//
//   test_corpus_duplicates CORPUS_DIR [EVERY]
//
// EVERY n: only every n-th scan (sorted by name; the sanitizer build).
// Every corpus scan is pushed once in frames of 4096 points, then again
// with every frame sent five times the way a resending scanner interleaves
// them: frame k, then the resends of frames k-1 .. k-4 (so a resend arrives
// up to four frames late), two of the four resends as exact copies and two
// as near-exact copies (each coordinate moved by one float ulp, as a
// resend through another conversion would). The status must be the same
// and the volume equal to 1e-6 relative.
//
// And (method surface, the default) every scan sent whole three times over,
// the copies one after another, far beyond the duplicate filter's window:
// the session's repeat mode (session/session.cpp) must keep the single
// copy's points, the same status and the volume within 5e-5 relative (the
// copies that arrive before the repeat is seen stay: at most a few dozen
// points). Without it a corpus scan's bins thinned three times as hard.
#include <dirent.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "scanio/scan_reader.h"
#include "test_session.h"

#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

constexpr size_t kFrame = 4096;
constexpr int kCopies = 5;
constexpr double kRelTol = 1e-6;

std::string g_dir;
size_t g_every = 1;

std::vector<pv_point_t> read_scan(const std::string &path) {
  pv::scanio::Error err;
  auto r = pv::scanio::open_scan(path, pv::scanio::Format::Auto, &err);
  std::vector<pv_point_t> pts;
  if (!r) return pts;
  std::vector<pv_point_t> buf(65536);
  long n;
  while ((n = r->read(buf.data(), buf.size(), &err)) > 0) pts.insert(pts.end(), buf.begin(), buf.begin() + n);
  return pts;
}

// Copy c of a frame: 0 the original, 1 and 3 exact, 2 and 4 near-exact.
std::vector<pv_point_t> frame_copy(const pv_point_t *p, size_t n, int c) {
  std::vector<pv_point_t> f(p, p + n);
  if (c % 2 == 1 || c == 0) return f;
  for (size_t i = 0; i < n; ++i) {
    // Copy 2 moves up on x and z, down on y; copy 4 the other way.
    const float dir = ((i + size_t(c / 2)) % 2) ? INFINITY : -INFINITY;
    f[i].x_mm = std::nextafter(f[i].x_mm, dir);
    f[i].y_mm = std::nextafter(f[i].y_mm, -dir);
    f[i].z_mm = std::nextafter(f[i].z_mm, dir);
  }
  return f;
}

// The scan pushed `copies` times over, one copy after the other.
pv_result_t measure_copies(const std::vector<pv_point_t> &pts, pv_method_t m, int copies) {
  TestSession b(m);
  for (int c = 0; c < copies; ++c) assert_int_equal(b.push_all(pts, kFrame), PV_OK);
  pv_result_t r{};
  // A refusal is a result too (compared below); the call must have made one.
  const pv_status_t st = pv_session_finish(b.s, &r);
  assert_int_equal(st, r.status);
  return r;
}

pv_result_t measure_once(const std::vector<pv_point_t> &pts, pv_method_t m) {
  return measure_copies(pts, m, 1);
}

pv_result_t measure_resent(const std::vector<pv_point_t> &pts, pv_method_t m) {
  TestSession b(m);
  const size_t frames = (pts.size() + kFrame - 1) / kFrame;
  auto send = [&](size_t k, int c) {
    const size_t from = k * kFrame, n = std::min(kFrame, pts.size() - from);
    const std::vector<pv_point_t> f = frame_copy(pts.data() + from, n, c);
    assert_int_equal(pv_session_push(b.s, f.data(), f.size()), PV_OK);
  };
  for (size_t k = 0; k < frames + kCopies - 1; ++k) {
    if (k < frames) send(k, 0);
    for (int c = 1; c < kCopies; ++c) {
      if (k >= size_t(c) && k - size_t(c) < frames) send(k - size_t(c), c);
    }
  }
  pv_result_t r{};
  const pv_status_t st = pv_session_finish(b.s, &r);
  assert_int_equal(st, r.status);
  return r;
}

std::vector<std::string> corpus_scans() {
  std::vector<std::string> v;
  DIR *d = opendir(g_dir.c_str());
  if (d == nullptr) return v;
  while (dirent *e = readdir(d)) {
    const std::string n = e->d_name;
    if (n.size() > 4 && n.compare(n.size() - 4, 4, ".ply") == 0) v.push_back(g_dir + "/" + n);
  }
  closedir(d);
  std::sort(v.begin(), v.end());
  std::vector<std::string> kept;
  for (size_t i = 0; i < v.size(); i += g_every) kept.push_back(v[i]);
  return kept;
}

void check_method(pv_method_t m) {
  const std::vector<std::string> scans = corpus_scans();
  assert_true(scans.size() >= 30 / g_every);
  int failures = 0;
  for (const std::string &path : scans) {
    const std::vector<pv_point_t> pts = read_scan(path);
    assert_true(pts.size() > 1000);
    const pv_result_t a = measure_once(pts, m);
    const pv_result_t b = measure_resent(pts, m);
    const double rel = a.status == PV_OK ? std::fabs(b.volume_cm3 - a.volume_cm3) / a.volume_cm3 : 0.0;
    std::printf("%-40s %-8s %-22s %12.4f cm3  x5: %-22s %12.4f cm3  rel %.2e\n",
                path.substr(path.rfind('/') + 1).c_str(), pv_method_name(m), pv_status_name(a.status),
                a.volume_cm3, pv_status_name(b.status), b.volume_cm3, rel);
    if (a.status != b.status || !(rel <= kRelTol)) ++failures;
  }
  assert_int_equal(failures, 0);
}

constexpr double kWholeRelTol = 5e-5;

void a_scan_sent_whole_again_measures_as_once(void **) {
  const std::vector<std::string> scans = corpus_scans();
  assert_true(scans.size() >= 30 / g_every);
  int failures = 0;
  for (const std::string &path : scans) {
    const std::vector<pv_point_t> pts = read_scan(path);
    const pv_result_t a = measure_once(pts, PV_METHOD_SURFACE);
    const pv_result_t b = measure_copies(pts, PV_METHOD_SURFACE, 3);
    const double rel = a.status == PV_OK ? std::fabs(b.volume_cm3 - a.volume_cm3) / a.volume_cm3 : 0.0;
    std::printf("%-40s surface %-22s %12.4f cm3  3 copies: %-22s %12.4f cm3  rel %.2e\n",
                path.substr(path.rfind('/') + 1).c_str(), pv_status_name(a.status), a.volume_cm3,
                pv_status_name(b.status), b.volume_cm3, rel);
    if (a.status != b.status || !(rel <= kWholeRelTol)) ++failures;
  }
  assert_int_equal(failures, 0);
}

void resent_frames_leave_the_paper_volume_unchanged(void **) { check_method(PV_METHOD_PAPER); }
void resent_frames_leave_the_polar_volume_unchanged(void **) { check_method(PV_METHOD_POLAR); }

}  // namespace

int main(int argc, char **argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: test_corpus_duplicates CORPUS_DIR [EVERY]\n");
    return 2;
  }
  g_dir = argv[1];
  if (argc == 3) g_every = std::max(1L, std::atol(argv[2]));
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(resent_frames_leave_the_paper_volume_unchanged),
      cmocka_unit_test(resent_frames_leave_the_polar_volume_unchanged),
      cmocka_unit_test(a_scan_sent_whole_again_measures_as_once),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
