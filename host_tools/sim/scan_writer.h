// Writes a simulated scan as the product sees it: a binary PLY file and the
// same points as a USB frame stream (docs/protocol/usb.md).
#ifndef PV_SIM_SCAN_WRITER_H
#define PV_SIM_SCAN_WRITER_H

#include <cstdint>
#include <string>
#include <vector>

#include "sim/handheld_scan.h"

namespace pv::sim {

struct WrittenScan {
  uint64_t points = 0;
  uint64_t frames = 0;       // USB frames written
  double tilt_deg = 0;
  std::vector<DropoutPatch> dropout_patches;  // pit frame
};

// Runs the scan to its end, streaming points to ply_path (binary little
// endian float; header comments carry the exact volume) and, if frames_path
// is not empty, USB frames to frames_path. Scanner frames larger than a USB
// frame are split; the last USB frame carries END_OF_SCAN. Returns false
// with *error set if a file cannot be written.
bool write_scan(const Pit &pit, const ScanParams &p, const std::string &ply_path,
                const std::string &frames_path, WrittenScan *out, std::string *error);

// A scan of several passes (sim/envelope.h): each pass a HandheldScan of
// the same pit with its own parameters, its points moved by a rigid motion
// given in the pit frame (registration jitter, a tracking slip):
//   q' = M (q - c) + c + d,
// applied to the world points as R M R^T (p - (R c + t)) + (R c + t) + R d
// with the pass's own world transform (R, t). The motion uses +, -, * only:
// the same bytes on every x86-64, like the scan.
struct PlanPass {
  ScanParams scan;
  double M[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double c[3] = {0, 0, 0};
  double d[3] = {0, 0, 0};
  bool moved = false;
};

struct ScanPlan {
  std::vector<PlanPass> passes;
  // The stream sent `copies` times: the whole of it again after its end,
  // or (interleave) each scanner frame `copies` times in a row.
  uint32_t copies = 1;
  bool interleave = false;
  // The PLY's coordinates are millimetres divided by this (10: centimetres,
  // 1000: metres); the frame stream stays in millimetres (the USB protocol's
  // unit). `unit` names it in the PLY header.
  double unit_divisor = 1.0;
  std::string unit = "mm";
};

struct WrittenPlan {
  WrittenScan scan;                  // points and frames written, pass 0's tilt
  std::vector<uint64_t> pass_points; // per pass, one copy
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {0, 0, 0};  // pass 0's transform
  WallCoverage coverage;             // all passes together
};

bool write_scan_plan(const Pit &pit, const ScanPlan &plan, const std::string &ply_path,
                     const std::string &frames_path, WrittenPlan *out, std::string *error);

}  // namespace pv::sim

#endif
