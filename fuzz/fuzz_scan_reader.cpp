// The scan file readers (host_tools/scanio) on arbitrary bytes, one binary
// per format (PV_FUZZ_FORMAT: Ply, Pcd or Xyz).
//
// Invariants beyond "no crash":
// - the same file read with a 65536-point buffer and with a small one
//   (1..16 points, from the input) ends the same way (the end, or an error
//   with the same message); read to its end it gives the same points, bit
//   for bit; on an error, the points of one are a prefix of the other's;
// - an error is sticky: read() again returns -1 with the same message;
// - after the end, read() keeps returning 0;
// - bytes_consumed() never exceeds bytes_total().
#include <algorithm>
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "scanio/scan_reader.h"

namespace {

using pv::scanio::Error;
using pv::scanio::Format;

struct Outcome {
  bool opened = false;
  std::vector<pv_point_t> points;
  bool failed = false;
  std::string message;
};

// The read buffer: allocated once, never cleared (the reader fills what it
// returns). A std::vector<pv_point_t>(65536) per read_all, value-initialised
// point by point under ASan and coverage, was 60 % of an execution. The cap
// points handed to read() end where the allocation ends, so ASan still
// catches a reader writing past cap.
constexpr size_t kMaxCap = 65536;
pv_point_t *read_buffer(size_t cap) {
  static pv_point_t *buf = new pv_point_t[kMaxCap];
  return buf + (kMaxCap - cap);
}

Outcome read_all(const std::string &path, size_t cap) {
  Outcome o;
  Error err;
  auto r = pv::scanio::open_scan(path, Format::PV_FUZZ_FORMAT, &err);
  if (!r) {
    o.message = err.message;
    PV_FUZZ_CHECK(!o.message.empty(), "open_scan failed without a message");
    return o;
  }
  o.opened = true;
  pv_point_t *buf = read_buffer(cap);
  for (;;) {
    const long n = r->read(buf, cap, &err);
    PV_FUZZ_CHECK(n >= -1 && n <= long(cap), "read returned %ld for cap %zu", n, cap);
    PV_FUZZ_CHECK(r->bytes_consumed() <= r->bytes_total(), "consumed %llu > total %llu",
                  (unsigned long long)r->bytes_consumed(), (unsigned long long)r->bytes_total());
    if (n < 0) {
      o.failed = true;
      o.message = err.message;
      PV_FUZZ_CHECK(!o.message.empty(), "read failed without a message");
      Error again;
      PV_FUZZ_CHECK(r->read(buf, cap, &again) == -1, "error not sticky");
      PV_FUZZ_CHECK(again.message == err.message, "sticky error changed: '%s' then '%s'",
                    err.message.c_str(), again.message.c_str());
      return o;
    }
    if (n == 0) {
      PV_FUZZ_CHECK(r->read(buf, cap, &err) == 0, "read after the end is not 0");
      return o;
    }
    o.points.insert(o.points.end(), buf, buf + n);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static pv::fuzz::MemFile file;
  const std::string &path = file.write(data, size);
  const size_t small = 1 + (size > 0 ? data[size - 1] % 16 : 0);
  const Outcome a = read_all(path, kMaxCap);
  const Outcome b = read_all(path, small);
  PV_FUZZ_CHECK(a.opened == b.opened && a.failed == b.failed && a.message == b.message,
                "outcome differs with buffer %zu: '%s' vs '%s'", small, a.message.c_str(),
                b.message.c_str());
  // A file read to its end gives the same points whatever the buffer. One
  // that fails may fail before a large buffer is handed back while a small
  // one already took the good points ahead of the damage: then the shorter
  // list is a prefix of the longer (the CLI refuses the file either way).
  if (!a.failed) {
    PV_FUZZ_CHECK(a.points.size() == b.points.size(), "%zu points vs %zu with buffer %zu",
                  a.points.size(), b.points.size(), small);
  }
  const size_t common = std::min(a.points.size(), b.points.size());
  PV_FUZZ_CHECK(common == 0 ||
                    std::memcmp(a.points.data(), b.points.data(), common * sizeof(pv_point_t)) == 0,
                "points differ with buffer %zu", small);
  return 0;
}
