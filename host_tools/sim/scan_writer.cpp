#include "sim/scan_writer.h"

#include <cstdio>
#include <memory>
#include <vector>

#include "pitvol/usb_frame.h"

namespace pv::sim {

namespace {

struct FileCloser {
  void operator()(FILE *f) const { std::fclose(f); }
};
using File = std::unique_ptr<FILE, FileCloser>;

// The PLY vertex count is not known until the scan ends: reserve a fixed
// width field in the header and fill it in afterwards.
constexpr int kCountWidth = 12;

void write_ply_header(FILE *f, const Pit &pit, uint64_t count) {
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\n"
               "comment pitvol-sim family %s ground %d seed %llu\n"
               "comment exact_volume_cm3 %.6f\n"
               "element vertex %*llu\nproperty float x\nproperty float y\nproperty float z\n"
               "end_header\n",
               family_name(pit.family), int(pit.ground), (unsigned long long)pit.seed,
               pit.volume_mm3 / 1000.0, kCountWidth, (unsigned long long)count);
}

class FrameStream {
 public:
  explicit FrameStream(FILE *f) : f_(f), buf_(PV_USB_MAX_FRAME_BYTES) {}
  // Queues points; a USB frame is written whenever one is full. The last
  // frame is held back so that END_OF_SCAN can be set on it.
  bool add(const Frame &fr) {
    for (const pv_point_t &p : fr.points) {
      if (pending_.size() == 3 * size_t(PV_USB_MAX_POINTS) && !flush(0)) return false;
      pending_.insert(pending_.end(), {p.x_mm, p.y_mm, p.z_mm});
      timestamp_us_ = fr.timestamp_us;
    }
    return true;
  }
  bool finish() { return flush(PV_USB_FLAG_END_OF_SCAN); }
  uint64_t frames() const { return sequence_; }

 private:
  bool flush(uint8_t flags) {
    pv_usb_frame_header_t h{PV_USB_FRAME_VERSION, flags, uint16_t(pending_.size() / 3),
                            uint32_t(sequence_), timestamp_us_};
    const size_t n = pv_usb_frame_encode(buf_.data(), buf_.size(), &h, pending_.data());
    pending_.clear();
    ++sequence_;
    return n > 0 && std::fwrite(buf_.data(), 1, n, f_) == n;
  }
  FILE *f_;
  std::vector<uint8_t> buf_;
  std::vector<float> pending_;
  uint64_t sequence_ = 0;
  uint64_t timestamp_us_ = 0;
};

}  // namespace

bool write_scan(const Pit &pit, const ScanParams &p, const std::string &ply_path,
                const std::string &frames_path, WrittenScan *out, std::string *error) {
  File ply(std::fopen(ply_path.c_str(), "wb"));
  if (!ply) {
    *error = "cannot write " + ply_path;
    return false;
  }
  File frames;
  if (!frames_path.empty()) {
    frames.reset(std::fopen(frames_path.c_str(), "wb"));
    if (!frames) {
      *error = "cannot write " + frames_path;
      return false;
    }
  }
  write_ply_header(ply.get(), pit, 0);
  FrameStream stream(frames.get());
  HandheldScan scan(pit, p);
  Frame fr;
  uint64_t count = 0;
  bool ok = true;
  while (ok && scan.next(&fr)) {
    ok = std::fwrite(fr.points.data(), sizeof(pv_point_t), fr.points.size(), ply.get()) ==
         fr.points.size();  // x86 and aarch64 are little endian
    if (frames) ok = ok && stream.add(fr);
    count += fr.points.size();
  }
  if (frames) ok = ok && stream.finish();
  // Rewrite the header now that the count is known (same length).
  ok = ok && std::fseek(ply.get(), 0, SEEK_SET) == 0;
  if (ok) write_ply_header(ply.get(), pit, count);
  ok = ok && std::fflush(ply.get()) == 0 && (!frames || std::fflush(frames.get()) == 0);
  if (!ok) {
    *error = "write failed for " + ply_path + (frames_path.empty() ? "" : " or " + frames_path);
    return false;
  }
  out->points = count;
  out->frames = stream.frames();
  out->tilt_deg = scan.tilt_deg();
  out->dropout_patches = scan.dropout_patches();
  return true;
}

}  // namespace pv::sim
