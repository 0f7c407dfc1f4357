// The USB frame reassembler (drivers/usb/usb_stream.c) on an arbitrary byte
// stream under arbitrary chunking.
//
// Invariants: the stream fed whole, byte by byte, and in random chunks
// (sizes drawn from the input) delivers the same frames (header and points,
// bit for bit) and the same statistics; every delivered point is finite and
// within the range; the counters add up (bytes_in is the input size,
// points_ok is the sum of delivered points).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "pitvol/usb_stream.h"

namespace {

constexpr float kMaxAbsMm = 1.0e5f;

struct Delivered {
  std::vector<pv_usb_frame_header_t> headers;
  std::vector<pv_point_t> points;
  std::vector<size_t> counts;
};

void on_points(void *user, const pv_usb_frame_header_t *h, const pv_point_t *p, size_t n) {
  auto *d = static_cast<Delivered *>(user);
  PV_FUZZ_CHECK(n <= PV_USB_MAX_POINTS, "%zu points in one frame", n);
  for (size_t i = 0; i < n; ++i) {
    PV_FUZZ_CHECK(std::isfinite(p[i].x_mm) && std::isfinite(p[i].y_mm) && std::isfinite(p[i].z_mm),
                  "non-finite point delivered");
    PV_FUZZ_CHECK(std::fabs(p[i].x_mm) <= kMaxAbsMm && std::fabs(p[i].y_mm) <= kMaxAbsMm &&
                      std::fabs(p[i].z_mm) <= kMaxAbsMm,
                  "out-of-range point delivered");
  }
  d->headers.push_back(*h);
  d->points.insert(d->points.end(), p, p + n);
  d->counts.push_back(n);
}

// The stream object is large (one frame buffer): one per chunking, static.
pv_usb_stream_t g_streams[3];

void run(pv_usb_stream_t *s, const uint8_t *data, size_t size, int mode, uint64_t seed,
         Delivered *d) {
  pv_usb_stream_init(s, kMaxAbsMm, on_points, d);
  pv::fuzz::Draw draw{seed};
  size_t at = 0;
  while (at < size) {
    size_t n = size - at;
    if (mode == 1) n = 1;
    if (mode == 2) n = std::min(n, 1 + draw.below(draw.below(4) == 0 ? 64 : PV_USB_MAX_FRAME_BYTES));
    pv_usb_stream_feed(s, data + at, n);
    at += n;
  }
  pv_usb_stream_feed(s, data + size, 0);  // an empty transfer changes nothing
}

bool same_headers(const Delivered &a, const Delivered &b) {
  if (a.headers.size() != b.headers.size()) return false;
  for (size_t i = 0; i < a.headers.size(); ++i) {
    const pv_usb_frame_header_t &x = a.headers[i], &y = b.headers[i];
    if (x.version != y.version || x.flags != y.flags || x.point_count != y.point_count ||
        x.sequence != y.sequence || x.timestamp_us != y.timestamp_us) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  uint64_t seed = 0;
  std::memcpy(&seed, data, std::min(size, sizeof seed));
  Delivered d[3];
  for (int mode = 0; mode < 3; ++mode) run(&g_streams[mode], data, size, mode, seed, &d[mode]);
  const pv_usb_stream_stats_t &s0 = g_streams[0].stats;
  PV_FUZZ_CHECK(s0.bytes_in == size, "bytes_in %llu of %zu", (unsigned long long)s0.bytes_in, size);
  PV_FUZZ_CHECK(s0.points_ok == d[0].points.size(), "points_ok %llu, delivered %zu",
                (unsigned long long)s0.points_ok, d[0].points.size());
  PV_FUZZ_CHECK(s0.frames_ok == d[0].headers.size(), "frames_ok %llu, delivered %zu",
                (unsigned long long)s0.frames_ok, d[0].headers.size());
  for (int mode = 1; mode < 3; ++mode) {
    PV_FUZZ_CHECK(std::memcmp(&g_streams[mode].stats, &s0, sizeof s0) == 0,
                  "statistics differ under chunking mode %d", mode);
    PV_FUZZ_CHECK(same_headers(d[0], d[mode]) && d[0].counts == d[mode].counts,
                  "frames differ under chunking mode %d", mode);
    PV_FUZZ_CHECK(d[0].points.size() == d[mode].points.size() &&
                      (d[0].points.empty() ||
                       std::memcmp(d[0].points.data(), d[mode].points.data(),
                                   d[0].points.size() * sizeof(pv_point_t)) == 0),
                  "points differ under chunking mode %d", mode);
  }
  return 0;
}
