// Volume from layer areas: see volume.h for decisions V1..V3.
#include "volume/volume.h"

#include <algorithm>
#include <cmath>

namespace pv {
namespace volume {
namespace {

// Same-spacing tolerance for "the limit coincides with the outermost layer".
constexpr double kSameZ_mm = 1e-9;

bool valid_sequence(const double *z, const double *s, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(z[i]) || !std::isfinite(s[i])) return false;
    if (i > 0 && !(z[i] > z[i - 1])) return false;
  }
  return true;
}

// 3-point rule exact for quadratics on uneven spacing (V1).
double simpson3(double z0, double z1, double z2, double s0, double s1, double s2) {
  const double h0 = z1 - z0, h1 = z2 - z1, h = h0 + h1;
  return h / 6.0 * ((2.0 - h1 / h0) * s0 + h * h / (h0 * h1) * s1 + (2.0 - h0 / h1) * s2);
}

// Frustum between two parallel sections (V2); exact for a cone.
double frustum(double z1, double z2, double s1, double s2) {
  const double g = std::sqrt(std::max(0.0, s1) * std::max(0.0, s2));
  return (z2 - z1) / 3.0 * (s1 + s2 + g);
}

// Value at z_at of the least-squares line through (z[i], s[i]), i in
// [first, first+m). Centred on the mean z so the 2x2 system is diagonal.
double line_at(const double *z, const double *s, size_t first, size_t m, double z_at) {
  double zbar = 0.0, sbar = 0.0;
  for (size_t i = first; i < first + m; ++i) {
    zbar += z[i];
    sbar += s[i];
  }
  zbar /= static_cast<double>(m);
  sbar /= static_cast<double>(m);
  double szz = 0.0, szs = 0.0;
  for (size_t i = first; i < first + m; ++i) {
    szz += (z[i] - zbar) * (z[i] - zbar);
    szs += (z[i] - zbar) * (s[i] - sbar);
  }
  const double slope = szz > 0.0 ? szs / szz : 0.0;  // m == 1: constant
  return sbar + slope * (z_at - zbar);
}

}  // namespace

double integrate_mm3(const double *z_mm, const double *area_mm2, size_t n) {
  if (z_mm == nullptr || area_mm2 == nullptr || n < 2) return 0.0;
  if (!valid_sequence(z_mm, area_mm2, n)) return 0.0;
  // Odd count: all triples. Even count: triples over the first n-1, frustum last.
  const size_t n_simpson = (n % 2 == 1) ? n : n - 1;
  double v = 0.0;
  for (size_t i = 0; i + 2 < n_simpson; i += 2)
    v += simpson3(z_mm[i], z_mm[i + 1], z_mm[i + 2], area_mm2[i], area_mm2[i + 1],
                  area_mm2[i + 2]);
  if (n % 2 == 0) v += frustum(z_mm[n - 2], z_mm[n - 1], area_mm2[n - 2], area_mm2[n - 1]);
  return v;
}

size_t scratch_needed_between(size_t n) { return 2 * (n + 2); }

bool volume_between_mm3(const double *z_mm, const double *area_mm2, size_t n,
                        const Limits &lim, double *scratch, size_t scratch_cap,
                        double *volume_mm3_out) {
  if (z_mm == nullptr || area_mm2 == nullptr || scratch == nullptr || volume_mm3_out == nullptr)
    return false;
  if (n < 2 || scratch_cap < scratch_needed_between(n)) return false;
  if (!valid_sequence(z_mm, area_mm2, n)) return false;
  if (!std::isfinite(lim.z_bottom_mm) || !std::isfinite(lim.z_rim_mm)) return false;
  if (!(lim.z_rim_mm > lim.z_bottom_mm)) return false;
  if (z_mm[0] < lim.z_bottom_mm - kSameZ_mm || z_mm[n - 1] > lim.z_rim_mm + kSameZ_mm)
    return false;

  const size_t m = std::min<size_t>(n, std::max<uint32_t>(1, lim.end_fit_layers));
  double *zs = scratch;
  double *ss = scratch + (n + 2);
  size_t k = 0;
  if (z_mm[0] - lim.z_bottom_mm > kSameZ_mm) {
    zs[k] = lim.z_bottom_mm;
    // An area cannot be negative; a steep contraction can extrapolate below 0.
    ss[k] = std::max(0.0, line_at(z_mm, area_mm2, 0, m, lim.z_bottom_mm));
    ++k;
  }
  for (size_t i = 0; i < n; ++i, ++k) {
    zs[k] = z_mm[i];
    ss[k] = area_mm2[i];
  }
  if (lim.z_rim_mm - z_mm[n - 1] > kSameZ_mm) {
    zs[k] = lim.z_rim_mm;
    ss[k] = std::max(0.0, line_at(z_mm, area_mm2, n - m, m, lim.z_rim_mm));
    ++k;
  }
  *volume_mm3_out = integrate_mm3(zs, ss, k);
  return true;
}

}  // namespace volume
}  // namespace pv
