// MAD sliding-window cleanup of the area sequence: see mad_filter.h (C1..C5).
#include "cleanup/mad_filter.h"

#include <algorithm>
#include <cmath>

namespace pv {
namespace cleanup {
namespace {

// 1 / Phi^-1(3/4): MAD * this = standard deviation for Gaussian data (C3).
constexpr double kMadToSigma = 1.4826;

// Median of buf[0..m), reordering buf. Full sort: m <= kMaxWindow, and the
// even-count average needs both middle values anyway.
double median_inplace(double *buf, size_t m) {
  std::sort(buf, buf + m);
  return (m % 2 == 1) ? buf[m / 2] : 0.5 * (buf[m / 2 - 1] + buf[m / 2]);
}

// Window [lo, lo + w) for position j of a sequence of length n (C2).
size_t window_start(size_t j, size_t n, size_t w, bool centred) {
  if (centred) {  // j in the middle, clamped at both ends of the sequence
    const size_t back = (w - 1) / 2;
    const size_t lo = j > back ? j - back : 0;
    return std::min(lo, n - w);
  }
  if (j < 3 || j + 1 < w) return 0;  // rim boundary, or trailing window clipped
  if (j + 3 >= n) return n - w;      // bottom boundary: last W values
  return j + 1 - w;                  // trailing window ending at j
}

// Robust local slope (area per mm) of the window: median of the slopes of
// adjacent pairs. Medians ignore a spike that breaks two of the W-1 pairs (C6).
double window_slope(const double *vals, const double *zs, size_t lo, size_t w) {
  if (w < 3) return 0.0;
  double buf[kMaxWindow];
  for (size_t i = 0; i + 1 < w; ++i)
    buf[i] = (vals[lo + i + 1] - vals[lo + i]) / (zs[lo + i + 1] - zs[lo + i]);
  return median_inplace(buf, w - 1);
}

// True when layer j lies outside median +- k sigma of the window
// [lo, lo + w) (C3), after removing the window's robust trend about z_j (C6).
bool is_outlier(const double *vals, const double *zs, size_t lo, size_t w, size_t j, double k,
                double floor_ratio, bool detrend, double sigma_floor) {
  const double slope = detrend ? window_slope(vals, zs, lo, w) : 0.0;
  double buf[kMaxWindow];
  for (size_t i = 0; i < w; ++i) buf[i] = vals[lo + i] - slope * (zs[lo + i] - zs[j]);
  const double med = median_inplace(buf, w);
  for (size_t i = 0; i < w; ++i)
    buf[i] = std::fabs(vals[lo + i] - slope * (zs[lo + i] - zs[j]) - med);
  const double mad = median_inplace(buf, w);
  const double sigma =
      std::max(std::max(kMadToSigma * mad, floor_ratio * std::fabs(med)), sigma_floor);
  return std::fabs(vals[j] - med) > k * sigma;
}

// Sequence-wide noise level from second differences: for i.i.d. noise of
// std sigma, d2 = e[j-1] - 2 e[j] + e[j+1] has std sqrt(6) sigma, and a smooth
// profile contributes ~0 to d2 (any trend or curvature cancels), so
// 1.4826 * median|d2| / sqrt(6) estimates sigma robustly (C7). Uses buf[0..m).
double global_sigma(const double *vals, const double *zs, size_t m, double *buf) {
  if (m < 3) return 0.0;
  for (size_t j = 1; j + 1 < m; ++j) {
    // Uneven spacing: second divided difference scaled back to unit steps.
    const double h0 = zs[j - 1] - zs[j], h1 = zs[j] - zs[j + 1];
    const double d2 = (vals[j - 1] - vals[j]) / h0 - (vals[j] - vals[j + 1]) / h1;
    buf[j - 1] = std::fabs(d2 * 0.5 * (h0 + h1));
  }
  // nth_element is enough here: the median of a large sequence, no average.
  const size_t cnt = m - 2, mid = cnt / 2;
  std::nth_element(buf, buf + mid, buf + cnt);
  return kMadToSigma * buf[mid] / std::sqrt(6.0);
}

bool usable(double area) { return std::isfinite(area) && area >= 0.0; }

}  // namespace

size_t scratch_needed(size_t n) { return 3 * n; }

size_t mad_filter(const double *z_mm, const double *area_mm2, size_t n, const Params &p,
                  uint8_t *keep_out, double *scratch, size_t scratch_cap) {
  if (keep_out == nullptr) return 0;
  for (size_t i = 0; i < n; ++i) keep_out[i] = 0;
  if (z_mm == nullptr || area_mm2 == nullptr || scratch == nullptr) return 0;
  if (scratch_cap < scratch_needed(n)) return 0;
  if (p.window_early == 0 || p.window_late == 0 || p.window_early > kMaxWindow ||
      p.window_late > kMaxWindow)
    return 0;

  // Negative / non-finite areas out first; the rest in the paper's order,
  // rim first (C1, C5).
  double *vals = scratch;
  double *zs = scratch + n;
  size_t m = 0;
  for (size_t i = n; i-- > 0;) {
    if (!usable(area_mm2[i]) || !std::isfinite(z_mm[i])) continue;
    vals[m] = area_mm2[i];
    zs[m] = z_mm[i];
    ++m;
  }
  if (m == 0) return 0;
  const double z_split = zs[m - 1] + p.split_mm;  // lowest layer + split
  const double s_floor = p.global_noise_floor ? global_sigma(vals, zs, m, scratch + 2 * n) : 0.0;

  // Decide every mark on the original sequence, then write back in input
  // order: walking i downward over usable layers visits them as j = 0, 1, ...
  size_t j = 0, kept = 0;
  for (size_t i = n; i-- > 0;) {
    if (!usable(area_mm2[i]) || !std::isfinite(z_mm[i])) continue;
    const bool early = zs[j] > z_split;
    const size_t w = std::min<size_t>(m, early ? p.window_early : p.window_late);
    const double k = early ? p.k_early : p.k_late;
    const bool out =
        is_outlier(vals, zs, window_start(j, m, w, p.centred), w, j, k, p.mad_floor_ratio, p.detrend, s_floor);
    keep_out[i] = out ? 0 : 1;
    kept += out ? 0 : 1;
    ++j;
  }
  return kept;
}

}  // namespace cleanup
}  // namespace pv
