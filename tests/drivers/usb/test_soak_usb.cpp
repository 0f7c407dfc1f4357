// Soak (label soak, not in CI; docs/reliability.md): 200 scans replayed back
// to back through the emulated USB scanner (umockdev) and the REAL libusb
// driver into ONE session block, pv_session_reset between scans, as a board
// in the field measures pit after pit without a restart.
//
// Checks:
//  - every result equals, bit for bit, the same scan measured alone in a
//    fresh session (status, volume, interval, depth, points in and used);
//  - no growth in open file descriptors (/proc/self/fd) between scan 10 and
//    scan 200: exactly the same count;
//  - no growth in resident memory (/proc/self/statm) between scan 10 and
//    scan 200 beyond kRssToleranceBytes (1 MiB: allocator slack; a leak of
//    one libusb transfer buffer (16 KiB) or one emulator frame buffer per
//    scan would pass it within 65 scans of the 190 watched).
//
// Scans: kDistinct small simulated scans (kPoints points each) of different
// pit families, replayed in turn. Usage: test_soak_usb [scans] (default 200).
#include <dirent.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pitvol/pitvol.h"
#include "pitvol/usb_scanner.h"
#include "sim/scan_writer.h"
#include "usb_emulator/emulated_scanner.h"

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kDistinct = 5;
constexpr uint32_t kPoints = 60000;
constexpr long kRssToleranceBytes = 1L << 20;  // 1 MiB
constexpr int kFirstMeasuredScan = 10;

const pv::sim::Family kFamilies[kDistinct] = {
    pv::sim::Family::Cylinder, pv::sim::Family::Tapered, pv::sim::Family::Bowl,
    pv::sim::Family::Elliptical, pv::sim::Family::HandDug};

long rss_bytes() {
  long pages_total = 0, pages_resident = 0;
  FILE *f = std::fopen("/proc/self/statm", "r");
  if (!f) return -1;
  const int n = std::fscanf(f, "%ld %ld", &pages_total, &pages_resident);
  std::fclose(f);
  return n == 2 ? pages_resident * sysconf(_SC_PAGESIZE) : -1;
}

// What each descriptor points to (printed when the count grew).
void list_fds() {
  DIR *d = opendir("/proc/self/fd");
  if (!d) return;
  while (dirent *e = readdir(d)) {
    if (e->d_name[0] == '.') continue;
    char target[512] = "";
    const std::string link = std::string("/proc/self/fd/") + e->d_name;
    const ssize_t n = readlink(link.c_str(), target, sizeof target - 1);
    if (n > 0) target[n] = '\0';
    std::fprintf(stderr, "  fd %s -> %s\n", e->d_name, target);
  }
  closedir(d);
}

int open_fds() {
  DIR *d = opendir("/proc/self/fd");
  if (!d) return -1;
  int n = 0;
  while (dirent *e = readdir(d)) {
    if (e->d_name[0] != '.') ++n;
  }
  closedir(d);
  return n - 1;  // the directory's own descriptor
}

struct Sink {
  pv_session_t *s;
  uint64_t points = 0;
  pv_status_t push_status = PV_OK;
};

void on_points(void *user, const pv_usb_frame_header_t *, const pv_point_t *pts, size_t n) {
  auto *k = static_cast<Sink *>(user);
  k->points += n;
  const pv_status_t st = pv_session_push(k->s, pts, n);
  if (st != PV_OK) k->push_status = st;
}

// One scan through emulator + driver into session s. False on a transport
// failure (message printed).
bool replay(const std::string &frames, pv_session_t *s, pv_result_t *out) {
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  char err[512] = "";
  pv_emu_t *emu = nullptr;
  if (pv_emu_create_from_file(&emu, frames.c_str(), &o, err, sizeof err) != 0) {
    std::fprintf(stderr, "emulator: %s\n", err);
    return false;
  }
  Sink sink{s};
  pv_usb_scanner_t *sc = nullptr;
  pv_usb_status_t ust = pv_usb_scanner_open(&sc, on_points, &sink);
  if (ust == PV_USB_OK) ust = pv_usb_scanner_start(sc);
  pv_usb_state_t state = PV_USB_STATE_IDLE;
  const auto t0 = Clock::now();
  while (ust == PV_USB_OK && state != PV_USB_STATE_ENDED &&
         std::chrono::duration<double>(Clock::now() - t0).count() < 60) {
    state = pv_usb_scanner_poll(sc, 100);
  }
  if (sc) pv_usb_scanner_close(sc);
  pv_emu_destroy(emu);
  if (ust != PV_USB_OK || state != PV_USB_STATE_ENDED || sink.push_status != PV_OK) {
    std::fprintf(stderr, "scan %s: usb status %d, state %d, push %s\n", frames.c_str(), int(ust),
                 int(state), pv_status_name(sink.push_status));
    return false;
  }
  // A refusal is a result (compared by the caller); the call must make one.
  *out = pv_result_t{};
  const pv_status_t fst = pv_session_finish(s, out);
  if (fst != out->status) {
    std::fprintf(stderr, "scan %s: finish: %s\n", frames.c_str(), pv_status_name(fst));
    return false;
  }
  return true;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_result(const pv_result_t &a, const pv_result_t &b) {
  return a.status == b.status && same_bits(a.volume_cm3, b.volume_cm3) &&
         same_bits(a.interval_cm3, b.interval_cm3) && same_bits(a.depth_mm, b.depth_mm) &&
         a.points_in == b.points_in && a.points_used == b.points_used && a.warnings == b.warnings;
}

struct Block {
  void *mem = nullptr;
  pv_session_t *s = nullptr;
  explicit Block(const pv_config_t &cfg) {
    size_t bytes = 0;
    if (pv_session_size(&cfg, &bytes) != PV_OK) return;  // s stays nullptr: the caller fails
    const size_t rounded = (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
    mem = std::aligned_alloc(PV_BLOCK_ALIGN, rounded);
    if (mem == nullptr || pv_session_init(&cfg, mem, rounded, &s) != PV_OK) s = nullptr;
  }
  ~Block() { std::free(mem); }
  Block(const Block &) = delete;
  Block &operator=(const Block &) = delete;
};

}  // namespace

int main(int argc, char **argv) {
  if (!pv_emu_available()) {
    std::printf("SKIP: not running under umockdev-wrapper\n");
    return 77;
  }
  const int scans = argc > 1 ? std::atoi(argv[1]) : 200;
  if (scans <= kFirstMeasuredScan) {
    std::fprintf(stderr, "usage: test_soak_usb [scans > %d]\n", kFirstMeasuredScan);
    return 2;
  }
  char tmpl[] = "/tmp/pitvol-soak-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return 1;
  const std::string dir = tmpl;

  // The scans, and each one's single-run result (a fresh session each).
  pv_config_t cfg;
  pv_config_default(&cfg);
  std::vector<std::string> frames(kDistinct), plys(kDistinct);
  std::vector<pv_result_t> single(kDistinct);
  for (int i = 0; i < kDistinct; ++i) {
    pv::sim::ScanParams p;
    p.seed = uint64_t(100 + i);
    p.target_points = kPoints;
    const pv::sim::Pit pit = pv::sim::make_pit(kFamilies[i], true, p.seed);
    plys[i] = dir + "/scan" + std::to_string(i) + ".ply";
    frames[i] = dir + "/scan" + std::to_string(i) + ".frames";
    pv::sim::WrittenScan w;
    std::string err;
    if (!pv::sim::write_scan(pit, p, plys[i], frames[i], &w, &err)) {
      std::fprintf(stderr, "scan %d: %s\n", i, err.c_str());
      return 1;
    }
    Block fresh(cfg);
    if (!fresh.s || !replay(frames[i], fresh.s, &single[i])) return 1;
    std::printf("# scan %d: %llu points, %llu frames: %s %.6f cm3\n", i, (unsigned long long)w.points,
                (unsigned long long)w.frames, pv_status_name(single[i].status), single[i].volume_cm3);
  }

  // The soak: one emulated scanner that stays plugged in, the driver opened
  // once, one block; per scan: the next pit loaded into the scanner, reset,
  // START, stream to END_OF_SCAN, finish.
  Block block(cfg);
  if (!block.s) return 1;
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  char err[512] = "";
  pv_emu_t *emu = nullptr;
  if (pv_emu_create_from_file(&emu, frames[0].c_str(), &o, err, sizeof err) != 0) {
    std::fprintf(stderr, "emulator: %s\n", err);
    return 1;
  }
  Sink sink{block.s};
  pv_usb_scanner_t *sc = nullptr;
  if (pv_usb_scanner_open(&sc, on_points, &sink) != PV_USB_OK) {
    std::fprintf(stderr, "cannot open the emulated scanner\n");
    return 1;
  }
  long rss_at_first = 0;
  int fds_at_first = 0;
  int mismatches = 0;
  const auto t0 = Clock::now();
  for (int k = 1; k <= scans; ++k) {
    const int i = (k - 1) % kDistinct;
    if (k > 1 && pv_emu_load_file(emu, frames[i].c_str(), err, sizeof err) != 0) {
      std::fprintf(stderr, "scan %d: emulator: %s\n", k, err);
      return 1;
    }
    if (k > 1 && pv_session_reset(block.s) != PV_OK) {
      std::fprintf(stderr, "reset failed before scan %d\n", k);
      return 1;
    }
    sink.points = 0;
    const pv_usb_status_t ust = pv_usb_scanner_start(sc);
    pv_usb_state_t state = PV_USB_STATE_IDLE;
    const auto ts = Clock::now();
    while (ust == PV_USB_OK && state != PV_USB_STATE_ENDED &&
           std::chrono::duration<double>(Clock::now() - ts).count() < 60) {
      state = pv_usb_scanner_poll(sc, 100);
    }
    if (ust != PV_USB_OK || state != PV_USB_STATE_ENDED || sink.push_status != PV_OK) {
      std::fprintf(stderr, "scan %d: usb status %d, state %d, push %s\n", k, int(ust), int(state),
                   pv_status_name(sink.push_status));
      return 1;
    }
    pv_result_t r{};
    const pv_status_t fst = pv_session_finish(block.s, &r);
    if (fst != r.status) {
      std::fprintf(stderr, "scan %d: finish: %s\n", k, pv_status_name(fst));
      return 1;
    }
    if (!same_result(r, single[i])) {
      ++mismatches;
      std::fprintf(stderr, "scan %d (%d): %s %.17g cm3 from %llu points, alone %s %.17g cm3\n", k, i,
                   pv_status_name(r.status), r.volume_cm3, (unsigned long long)sink.points,
                   pv_status_name(single[i].status), single[i].volume_cm3);
    }
    if (k == kFirstMeasuredScan) {
      rss_at_first = rss_bytes();
      fds_at_first = open_fds();
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const long rss_end = rss_bytes();
  const int fds_end = open_fds();
  pv_usb_scanner_stats_t us;
  pv_usb_scanner_get_stats(sc, &us);
  pv_usb_scanner_close(sc);
  pv_emu_destroy(emu);
  std::printf("# driver: %llu frames, %llu lost, %llu bad CRC, %llu scans ended, %llu transfer errors\n",
              (unsigned long long)us.stream.frames_ok, (unsigned long long)us.stream.frames_lost,
              (unsigned long long)us.stream.frames_bad_crc, (unsigned long long)us.stream.scans_ended,
              (unsigned long long)us.transfer_errors);
  std::printf("# %d scans in %.1f s (%.2f s per scan); RSS at scan %d %ld KiB, at scan %d %ld KiB "
              "(growth %ld KiB, tolerance %ld KiB); open fds %d and %d; %d results differ\n",
              scans, seconds, seconds / scans, kFirstMeasuredScan, rss_at_first / 1024, scans,
              rss_end / 1024, (rss_end - rss_at_first) / 1024, kRssToleranceBytes / 1024,
              fds_at_first, fds_end, mismatches);
  for (int i = 0; i < kDistinct; ++i) {
    std::remove(plys[i].c_str());
    std::remove(frames[i].c_str());
  }
  rmdir(dir.c_str());
  int failed = 0;
  if (mismatches) {
    std::fprintf(stderr, "FAIL: %d of %d results differ from their single-run values\n", mismatches, scans);
    failed = 1;
  }
  if (fds_end != fds_at_first) {
    std::fprintf(stderr, "FAIL: open file descriptors %d at scan %d, %d at scan %d:\n", fds_at_first,
                 kFirstMeasuredScan, fds_end, scans);
    list_fds();
    failed = 1;
  }
  if (us.stream.frames_lost != 0 || us.stream.frames_bad_crc != 0 ||
      us.stream.scans_ended != uint64_t(scans) || us.transfer_errors != 0) {
    std::fprintf(stderr, "FAIL: the driver lost frames or scans (see the line above)\n");
    failed = 1;
  }
  if (rss_at_first <= 0 || rss_end - rss_at_first > kRssToleranceBytes) {
    std::fprintf(stderr, "FAIL: resident memory grew by %ld KiB (tolerance %ld KiB)\n",
                 (rss_end - rss_at_first) / 1024, kRssToleranceBytes / 1024);
    failed = 1;
  }
  return failed;
}
