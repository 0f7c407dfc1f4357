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

// The PLY file, and the frame stream's unless its path is empty.
bool open_outputs(const std::string &ply_path, const std::string &frames_path, File *ply,
                  File *frames, std::string *error) {
  ply->reset(std::fopen(ply_path.c_str(), "wb"));
  if (!*ply) {
    *error = "cannot write " + ply_path;
    return false;
  }
  if (!frames_path.empty()) {
    frames->reset(std::fopen(frames_path.c_str(), "wb"));
    if (!*frames) {
      *error = "cannot write " + frames_path;
      return false;
    }
  }
  return true;
}

// The plan's PLY header: as write_ply_header, and the unit and passes.
void write_plan_header(FILE *f, const Pit &pit, const ScanPlan &plan, uint64_t count) {
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\n"
               "comment pitvol-sim family %s ground %d seed %llu\n"
               "comment exact_volume_cm3 %.6f\n"
               "comment units %s passes %zu copies %u\n"
               "element vertex %*llu\nproperty float x\nproperty float y\nproperty float z\n"
               "end_header\n",
               family_name(pit.family), int(pit.ground), (unsigned long long)pit.seed,
               pit.volume_mm3 / 1000.0, plan.unit.c_str(), plan.passes.size(),
               unsigned(plan.copies), kCountWidth, (unsigned long long)count);
}

// The pass's motion in the world frame: A = R M R^T, b = (R c + t) - A (R c
// + t) + R d, so that p' = A p + b.
void world_motion(const PlanPass &ps, const double R[9], const double t[3], double A[9],
                  double b[3]) {
  double RM[9];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      RM[3 * i + k] = R[3 * i] * ps.M[k] + R[3 * i + 1] * ps.M[3 + k] + R[3 * i + 2] * ps.M[6 + k];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)  // (R M) R^T
      A[3 * i + k] = RM[3 * i] * R[3 * k] + RM[3 * i + 1] * R[3 * k + 1] + RM[3 * i + 2] * R[3 * k + 2];
  double cw[3], dw[3];
  for (int i = 0; i < 3; ++i) {
    cw[i] = R[3 * i] * ps.c[0] + R[3 * i + 1] * ps.c[1] + R[3 * i + 2] * ps.c[2] + t[i];
    dw[i] = R[3 * i] * ps.d[0] + R[3 * i + 1] * ps.d[1] + R[3 * i + 2] * ps.d[2];
  }
  for (int i = 0; i < 3; ++i)
    b[i] = cw[i] - (A[3 * i] * cw[0] + A[3 * i + 1] * cw[1] + A[3 * i + 2] * cw[2]) + dw[i];
}

}  // namespace

bool write_scan_plan(const Pit &pit, const ScanPlan &plan, const std::string &ply_path,
                     const std::string &frames_path, WrittenPlan *out, std::string *error) {
  File ply, frames;
  if (!open_outputs(ply_path, frames_path, &ply, &frames, error)) return false;
  write_plan_header(ply.get(), pit, plan, 0);
  FrameStream stream(frames.get());
  const uint32_t copies = plan.copies < 1 ? 1 : plan.copies;
  uint64_t count = 0;
  bool ok = true;
  std::vector<pv_point_t> scaled;
  auto emit = [&](const Frame &fr) {
    const std::vector<pv_point_t> *pts = &fr.points;
    if (plan.unit_divisor != 1.0) {
      scaled.resize(fr.points.size());
      for (size_t i = 0; i < fr.points.size(); ++i) {
        const pv_point_t &p = fr.points[i];
        scaled[i] = pv_point_t{static_cast<float>(static_cast<double>(p.x_mm) / plan.unit_divisor),
                               static_cast<float>(static_cast<double>(p.y_mm) / plan.unit_divisor),
                               static_cast<float>(static_cast<double>(p.z_mm) / plan.unit_divisor)};
      }
      pts = &scaled;
    }
    ok = ok && std::fwrite(pts->data(), sizeof(pv_point_t), pts->size(), ply.get()) == pts->size();
    if (frames) ok = ok && stream.add(fr);
    count += fr.points.size();
  };
  std::vector<Frame> kept;  // whole-stream copies: the frames again at the end
  std::vector<double> cell_area;
  std::vector<uint32_t> cell_hits;
  out->pass_points.clear();
  for (size_t k = 0; ok && k < plan.passes.size(); ++k) {
    const PlanPass &ps = plan.passes[k];
    HandheldScan scan(pit, ps.scan);
    double R[9], t[3], A[9], b[3];
    scan.transform(R, t);
    if (k == 0) {
      for (int i = 0; i < 9; ++i) out->R[i] = R[i];
      for (int i = 0; i < 3; ++i) out->t[i] = t[i];
      out->scan.tilt_deg = scan.tilt_deg();
      out->scan.dropout_patches = scan.dropout_patches();
    }
    if (ps.moved) world_motion(ps, R, t, A, b);
    Frame fr;
    uint64_t n = 0;
    while (ok && scan.next(&fr)) {
      if (ps.moved) {
        for (pv_point_t &p : fr.points) {
          const double x = p.x_mm, y = p.y_mm, z = p.z_mm;
          p.x_mm = static_cast<float>(A[0] * x + A[1] * y + A[2] * z + b[0]);
          p.y_mm = static_cast<float>(A[3] * x + A[4] * y + A[5] * z + b[1]);
          p.z_mm = static_cast<float>(A[6] * x + A[7] * y + A[8] * z + b[2]);
        }
      }
      n += fr.points.size();
      const uint32_t now = plan.interleave ? copies : 1;
      for (uint32_t c = 0; c < now; ++c) emit(fr);
      if (!plan.interleave && copies > 1) kept.push_back(fr);
    }
    out->pass_points.push_back(n);
    std::vector<double> area;
    std::vector<uint32_t> hits;
    scan.wall_cells(&area, &hits);
    if (cell_area.empty()) {
      cell_area = area;
      cell_hits.assign(area.size(), 0);
    }
    for (size_t i = 0; i < hits.size() && i < cell_hits.size(); ++i) cell_hits[i] += hits[i];
  }
  for (uint32_t c = 1; ok && !plan.interleave && c < copies; ++c)
    for (const Frame &fr : kept) emit(fr);
  if (frames) ok = ok && stream.finish();
  ok = ok && std::fseek(ply.get(), 0, SEEK_SET) == 0;
  if (ok) write_plan_header(ply.get(), pit, plan, count);
  ok = ok && std::fflush(ply.get()) == 0 && (!frames || std::fflush(frames.get()) == 0);
  if (!ok) {
    *error = "write failed for " + ply_path + (frames_path.empty() ? "" : " or " + frames_path);
    return false;
  }
  out->scan.points = count;
  out->scan.frames = stream.frames();
  out->coverage = wall_coverage_of(cell_area, cell_hits);
  return true;
}

bool write_scan(const Pit &pit, const ScanParams &p, const std::string &ply_path,
                const std::string &frames_path, WrittenScan *out, std::string *error) {
  File ply, frames;
  if (!open_outputs(ply_path, frames_path, &ply, &frames, error)) return false;
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
