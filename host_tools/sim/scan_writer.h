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

}  // namespace pv::sim

#endif
