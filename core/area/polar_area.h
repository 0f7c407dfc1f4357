// Cross-section area from a Fourier series r(theta) fitted by least squares
// (method "polar"; not in the paper).
//
// Why: the paper's y(x) cubic halves need many points per piece near the
// contour's vertical tangents, and its clustering keeps one band of radius,
// which cuts elongated sections. Measured on the corpus (docs/accuracy.md):
// sparse lower walls read 2-3 % low, ellipses up to 26 % low. A periodic
// r(theta) = a0 + sum_k (a_k cos k theta + b_k sin k theta) has no tangent
// problem, follows elongated and irregular sections with a few harmonics,
// and its enclosed area is exact: pi a0^2 + pi/2 sum_k (a_k^2 + b_k^2).
//
// Robustness: centred on the coordinate-wise median (strays cannot drag
// it); fitted twice, the second time without the points whose residual
// exceeds max(min_band_mm, 3 x 1.4826 MAD) (multipath floating in front of the
// wall, interior strays). The order is capped by the point count and by the
// largest angular gap (a harmonic may not oscillate freely across a gap:
// K <= pi / gap), so an unseen stretch is bridged smoothly.
// No allocation: fixed-maximum-size Eigen matrices, caller scratch.
#ifndef PV_AREA_POLAR_AREA_H
#define PV_AREA_POLAR_AREA_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv::area {

constexpr uint32_t kMaxHarmonics = 12;

struct PolarParams {
  uint32_t max_harmonics = 10;
  uint32_t points_per_coefficient = 6;  // K <= n / (2 * this)
  double min_band_mm = 1.0;             // residual band floor for trimming
  double max_gap_deg = 90.0;            // larger angular gap: refuse
};

struct PolarResult {
  double area_mm2 = 0;
  uint32_t harmonics = 0;
  uint32_t points_used = 0;  // after trimming
  double max_gap_deg = 0;
};

// scratch: polar_scratch_needed(n) doubles.
size_t polar_scratch_needed(size_t n);
bool polar_area(const XY *pts, size_t n, const PolarParams &p, double *scratch, size_t scratch_cap,
                PolarResult *out);

}  // namespace pv::area

#endif
