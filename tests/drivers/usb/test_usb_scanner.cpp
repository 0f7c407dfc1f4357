// The REAL libusb driver (drivers/usb/usb_scanner_libusb.c) against the
// emulated USB scanner (host_tools/usb_emulator, umockdev): no mocks of
// libusb. Runs under umockdev-wrapper (CTest does that); exits 77 (skip)
// without it.
//
// The fixture scan is made at test time, as `pitvol-sim scan --family
// cylinder --seed 3 --out DIR/cyl` does: DIR/cyl.ply and DIR/cyl.frames.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "pitvol/pitvol.h"
#include "pitvol/usb_scanner.h"
#include "scanio/scan_reader.h"
#include "sim/scan_writer.h"
#include "usb_emulator/emulated_scanner.h"

#include "pv_cmocka.h"

namespace {

using Clock = std::chrono::steady_clock;

std::string g_dir;
std::string g_frames;
std::string g_ply;

// A core session in its own block.
struct Session {
  void *block = nullptr;
  pv_session_t *s = nullptr;
  uint64_t points = 0;
  pv_status_t push_status = PV_OK;  // the first push refused (checked after the run)
  Session() {
    pv_config_t cfg;
    pv_config_default(&cfg);
    size_t bytes = 0;
    assert_int_equal(pv_session_size(&cfg, &bytes), PV_OK);
    block = std::aligned_alloc(PV_BLOCK_ALIGN, (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN);
    if (block == nullptr || pv_session_init(&cfg, block, bytes, &s) != PV_OK) s = nullptr;
  }
  ~Session() { std::free(block); }
  Session(const Session &) = delete;
  Session &operator=(const Session &) = delete;
};

void on_points(void *user, const pv_usb_frame_header_t *, const pv_point_t *pts, size_t n) {
  auto *s = static_cast<Session *>(user);
  s->points += n;
  // Not asserted here: cmocka's failure would jump out through libusb.
  const pv_status_t st = pv_session_push(s->s, pts, n);
  if (st != PV_OK && s->push_status == PV_OK) s->push_status = st;
}

// The PLY through scanio into a session: the reference.
pv_result_t ply_result() {
  static bool done = false;
  static pv_result_t r{};
  if (done) return r;
  Session s;
  assert_non_null(s.s);
  pv::scanio::Error err;
  auto reader = pv::scanio::open_scan(g_ply, pv::scanio::Format::Auto, &err);
  assert_non_null(reader.get());
  std::vector<pv_point_t> chunk(65536);
  long n;
  while ((n = reader->read(chunk.data(), chunk.size(), &err)) > 0) {
    assert_int_equal(pv_session_push(s.s, chunk.data(), size_t(n)), PV_OK);
  }
  assert_int_equal(n, 0);
  assert_int_equal(pv_session_finish(s.s, &r), PV_OK);
  assert_int_equal(r.status, PV_OK);
  done = true;
  return r;
}

struct UsbRun {
  pv_result_t result{};
  pv_usb_scanner_stats_t usb{};
  pv_emu_stats_t emu{};
  pv_usb_state_t state = PV_USB_STATE_IDLE;
  uint64_t points = 0;
};

// Streams the fixture through emulator + driver until END_OF_SCAN.
UsbRun run_usb(const pv_emu_options_t &o, int timeout_s = 60) {
  UsbRun run;
  char err[512] = "";
  pv_emu_t *emu = nullptr;
  if (pv_emu_create_from_file(&emu, g_frames.c_str(), &o, err, sizeof err) != 0) {
    fail_msg("emulator: %s", err);
  }
  Session s;
  assert_non_null(s.s);
  pv_usb_scanner_t *sc = nullptr;
  assert_int_equal(pv_usb_scanner_open(&sc, on_points, &s), PV_USB_OK);
  assert_int_equal(pv_usb_scanner_start(sc), PV_USB_OK);
  const auto t0 = Clock::now();
  while (run.state != PV_USB_STATE_ENDED &&
         std::chrono::duration<double>(Clock::now() - t0).count() < timeout_s) {
    run.state = pv_usb_scanner_poll(sc, 100);
  }
  pv_usb_scanner_get_stats(sc, &run.usb);
  pv_usb_scanner_close(sc);
  pv_emu_stats(emu, &run.emu);
  pv_emu_destroy(emu);
  run.points = s.points;
  assert_int_equal(s.push_status, PV_OK);
  // A refusal is a result the callers check; the call must have made one.
  const pv_status_t st = pv_session_finish(s.s, &run.result);
  assert_int_equal(st, run.result.status);
  return run;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// (1) The same scan through USB and from its PLY: the same volume, bit for bit.
void test_replay_matches_ply(void **) {
  const pv_result_t ref = ply_result();
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  const UsbRun run = run_usb(o);
  std::printf("# usb %.9f cm3, ply %.9f cm3, %llu points\n", run.result.volume_cm3, ref.volume_cm3,
              (unsigned long long)run.points);
  assert_int_equal(run.state, PV_USB_STATE_ENDED);
  assert_int_equal(run.result.status, PV_OK);
  assert_true(same_bits(run.result.volume_cm3, ref.volume_cm3));
  assert_true(same_bits(run.result.depth_mm, ref.depth_mm));
  assert_int_equal(run.result.points_in, ref.points_in);
  assert_int_equal(run.points, run.emu.points_in);
  assert_int_equal(run.usb.stream.frames_ok, run.emu.frames_in);
  assert_int_equal(run.usb.stream.frames_bad_crc, 0);
  assert_int_equal(run.usb.stream.frames_lost, 0);
  assert_int_equal(run.usb.stream.bytes_skipped, 0);
  assert_int_equal(run.usb.stream.bytes_in, run.emu.bytes_out);
  assert_int_equal(run.usb.stream.scans_ended, 1);
  assert_int_equal(run.usb.transfer_errors, 0);
}

// (1b) Split differently on the wire (random short URBs): still bit for bit.
void test_short_reads_match_ply(void **) {
  const pv_result_t ref = ply_result();
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  o.short_reads = 1;
  o.seed = 11;
  const UsbRun run = run_usb(o);
  assert_int_equal(run.state, PV_USB_STATE_ENDED);
  assert_true(run.usb.transfers_short > 10);
  assert_true(same_bits(run.result.volume_cm3, ref.volume_cm3));
  assert_int_equal(run.usb.stream.frames_lost, 0);
}

// (2) 10 % of frames with a bad CRC: each one counted, volume within 1 %.
void test_corrupt_frames_counted(void **) {
  const pv_result_t ref = ply_result();
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  o.corrupt_rate = 0.10;
  o.seed = 7;
  const UsbRun run = run_usb(o);
  const double rel = std::fabs(run.result.volume_cm3 - ref.volume_cm3) / ref.volume_cm3;
  std::printf("# clean %.3f cm3, 10 %% corrupt %.3f cm3 (%.3f %%), %llu of %llu frames corrupted\n",
              ref.volume_cm3, run.result.volume_cm3, 100.0 * rel,
              (unsigned long long)run.emu.frames_corrupted, (unsigned long long)run.emu.frames_out);
  assert_int_equal(run.state, PV_USB_STATE_ENDED);
  assert_true(run.emu.frames_corrupted > 0);
  assert_int_equal(run.usb.stream.frames_bad_crc, run.emu.frames_corrupted);
  assert_int_equal(run.usb.stream.frames_lost, run.emu.frames_corrupted);
  assert_int_equal(run.usb.stream.frames_ok, run.emu.frames_out - run.emu.frames_corrupted);
  assert_int_equal(run.points, run.emu.points_in - run.emu.points_corrupted);
  assert_int_equal(run.result.status, PV_OK);
  assert_true(rel < 0.01);
}

// (3) Unplug half way through frame N: the partial scan and UNPLUGGED come
// back, points so far kept; after the replug the scan resumes and completes.
void test_unplug_and_replug(void **) {
  const pv_result_t ref = ply_result();
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  char err[512] = "";
  pv_emu_t *probe = nullptr;
  assert_int_equal(pv_emu_create_from_file(&probe, g_frames.c_str(), &o, err, sizeof err), 0);
  const uint64_t n = pv_emu_frame_count(probe) / 2;
  pv_emu_destroy(probe);

  o.unplug_at_frame = int64_t(n);
  o.replug_after_ms = -1;  // on request, so that the test sees the gap
  pv_emu_t *emu = nullptr;
  assert_int_equal(pv_emu_create_from_file(&emu, g_frames.c_str(), &o, err, sizeof err), 0);
  Session s;
  pv_usb_scanner_t *sc = nullptr;
  assert_int_equal(pv_usb_scanner_open(&sc, on_points, &s), PV_USB_OK);
  assert_int_equal(pv_usb_scanner_start(sc), PV_USB_OK);
  pv_usb_state_t st = PV_USB_STATE_STREAMING;
  auto t0 = Clock::now();
  while (st != PV_USB_STATE_UNPLUGGED && std::chrono::duration<double>(Clock::now() - t0).count() < 30) {
    st = pv_usb_scanner_poll(sc, 100);
    assert_int_not_equal(st, PV_USB_STATE_ENDED);
  }
  assert_int_equal(st, PV_USB_STATE_UNPLUGGED);
  // Stays unplugged while the device is away; the partial scan is kept.
  for (int i = 0; i < 5; ++i) assert_int_equal(pv_usb_scanner_poll(sc, 60), PV_USB_STATE_UNPLUGGED);
  pv_usb_scanner_stats_t us;
  pv_usb_scanner_get_stats(sc, &us);
  const uint64_t before = pv_emu_points_before_frame(emu, n);
  std::printf("# unplugged at frame %llu: %llu points kept, %llu partial bytes dropped\n",
              (unsigned long long)n, (unsigned long long)s.points,
              (unsigned long long)us.stream.bytes_skipped);
  assert_int_equal(us.unplugs, 1);
  assert_int_equal(us.replugs, 0);
  assert_int_equal(s.points, before);
  assert_int_equal(us.stream.frames_ok, n);
  assert_true(us.stream.bytes_skipped > 0);  // the half frame
  pv_result_t partial{};
  // Half a pit may not support an estimate yet; the points are there.
  (void)pv_session_estimate(s.s, &partial);
  assert_int_equal(partial.points_in, before);

  assert_int_equal(pv_emu_replug(emu), 0);
  t0 = Clock::now();
  while (st != PV_USB_STATE_ENDED && std::chrono::duration<double>(Clock::now() - t0).count() < 30) {
    st = pv_usb_scanner_poll(sc, 100);
  }
  assert_int_equal(st, PV_USB_STATE_ENDED);
  pv_usb_scanner_get_stats(sc, &us);
  pv_usb_scanner_close(sc);
  pv_emu_stats_t es;
  pv_emu_stats(emu, &es);
  pv_emu_destroy(emu);
  assert_int_equal(us.unplugs, 1);
  assert_int_equal(us.replugs, 1);
  assert_int_equal(es.starts, 2);  // START sent again after the replug
  assert_int_equal(us.stream.frames_lost, 0);
  assert_int_equal(us.stream.scans_ended, 1);
  assert_int_equal(s.points, es.points_in);
  assert_int_equal(s.push_status, PV_OK);
  pv_result_t r{};
  assert_int_equal(pv_session_finish(s.s, &r), PV_OK);
  assert_true(same_bits(r.volume_cm3, ref.volume_cm3));
}

// (3b) Unplug with an automatic replug 150 ms later (hotplug path).
void test_unplug_timed_replug(void **) {
  const pv_result_t ref = ply_result();
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  o.unplug_at_frame = 20;
  o.replug_after_ms = 150;
  const UsbRun run = run_usb(o);
  assert_int_equal(run.state, PV_USB_STATE_ENDED);
  assert_int_equal(run.usb.unplugs, 1);
  assert_int_equal(run.usb.replugs, 1);
  assert_int_equal(run.usb.stream.frames_lost, 0);
  assert_true(same_bits(run.result.volume_cm3, ref.volume_cm3));
}

// (4) A stall mid-stream is cleared and no point is lost.
void test_stall_cleared(void **) {
  const pv_result_t ref = ply_result();
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  o.stall_at_frame = 30;
  const UsbRun run = run_usb(o);
  assert_int_equal(run.state, PV_USB_STATE_ENDED);
  assert_true(run.emu.urbs_stalled >= 1);
  assert_true(run.usb.stalls_cleared >= 1);
  assert_int_equal(run.usb.stalls_cleared, run.emu.clear_halts);
  assert_int_equal(run.usb.stream.frames_lost, 0);
  assert_int_equal(run.usb.stream.frames_ok, run.emu.frames_out);
  assert_int_equal(run.points, run.emu.points_in);
  assert_true(same_bits(run.result.volume_cm3, ref.volume_cm3));
}

// Duplicates are dropped and counted, dropped frames show as gaps.
void test_duplicates_and_drops(void **) {
  pv_emu_options_t o;
  pv_emu_options_default(&o);
  o.duplicate_rate = 0.1;
  o.drop_rate = 0.05;
  o.seed = 5;
  const UsbRun run = run_usb(o);
  assert_int_equal(run.state, PV_USB_STATE_ENDED);
  assert_int_equal(run.usb.stream.frames_duplicate, run.emu.frames_duplicated);
  assert_int_equal(run.usb.stream.frames_lost, run.emu.frames_dropped);
  assert_int_equal(run.points, run.emu.points_in - run.emu.points_dropped);
}

int setup(void **) {
  char tmpl[] = "/tmp/pitvol-usb-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return -1;
  g_dir = tmpl;
  g_ply = g_dir + "/cyl.ply";
  g_frames = g_dir + "/cyl.frames";
  // As `pitvol-sim scan --family cylinder --seed 3` (ground on by default).
  pv::sim::ScanParams p;
  p.seed = 3;
  const pv::sim::Pit pit = pv::sim::make_pit(pv::sim::Family::Cylinder, true, 3);
  pv::sim::WrittenScan w;
  std::string err;
  if (!pv::sim::write_scan(pit, p, g_ply, g_frames, &w, &err)) {
    std::fprintf(stderr, "fixture: %s\n", err.c_str());
    return -1;
  }
  std::printf("# fixture %s: %llu points, %llu USB frames\n", g_dir.c_str(),
              (unsigned long long)w.points, (unsigned long long)w.frames);
  return 0;
}

int teardown(void **) {
  std::remove(g_ply.c_str());
  std::remove(g_frames.c_str());
  rmdir(g_dir.c_str());
  return 0;
}

}  // namespace

int main() {
  if (!pv_emu_available()) {
    std::printf("SKIP: not running under umockdev-wrapper\n");
    return 77;
  }
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_replay_matches_ply),
      cmocka_unit_test(test_short_reads_match_ply),
      cmocka_unit_test(test_corrupt_frames_counted),
      cmocka_unit_test(test_unplug_and_replug),
      cmocka_unit_test(test_unplug_timed_replug),
      cmocka_unit_test(test_stall_cleared),
      cmocka_unit_test(test_duplicates_and_drops),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
