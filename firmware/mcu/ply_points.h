// Minimal streaming reader of binary little-endian PLY vertices, for the
// replay program on every target (stdio only: newlib semihosting on the
// MCU). The host tools have the full reader (host_tools/scanio); this one
// is small on purpose: fixed-size scalar properties, x/y/z as float or
// double, the vertex element first. Anything else is refused with a reason.
#ifndef PV_FIRMWARE_PLY_POINTS_H
#define PV_FIRMWARE_PLY_POINTS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "pitvol/pitvol.h"

namespace pv::firmware {

class PlyPoints {
 public:
  PlyPoints() = default;
  PlyPoints(const PlyPoints &) = delete;
  PlyPoints &operator=(const PlyPoints &) = delete;
  ~PlyPoints();
  // Reads the header; false with error() set if the file is unusable.
  bool open(const char *path);
  // Up to cap points into out; 0 at the end or on error (see error()).
  size_t read(pv_point_t *out, size_t cap);
  // NULL while all is well.
  const char *error() const { return error_; }

 private:
  bool fail(const char *why);

  FILE *f_ = nullptr;
  const char *error_ = nullptr;
  uint64_t remaining_ = 0;
  size_t stride_ = 0;
  size_t offset_[3] = {0, 0, 0};
  bool is_double_[3] = {false, false, false};
  unsigned char buf_[64 * 1024] = {};
};

}  // namespace pv::firmware

#endif
