// Per-layer clustering: see clustering.h for the method and the decisions.
#include "clustering/clustering.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/angle.h"
#include "thinning/adaptive_thinning.h"

namespace pv {
namespace clustering {

namespace {

struct Box {
  double x_min, x_max, y_min, y_max;
};

Box bounding_box(const XY *pts, size_t n) {
  Box b{pts[0].x_mm, pts[0].x_mm, pts[0].y_mm, pts[0].y_mm};
  for (size_t i = 1; i < n; ++i) {
    b.x_min = std::min(b.x_min, pts[i].x_mm);
    b.x_max = std::max(b.x_max, pts[i].x_mm);
    b.y_min = std::min(b.y_min, pts[i].y_mm);
    b.y_max = std::max(b.y_max, pts[i].y_mm);
  }
  return b;
}

// Extent along `other` of the points whose `axis` coordinate is within
// strip_mm of axis_max. axis/other: 0 = x, 1 = y.
double cross_range_mm(const XY *pts, size_t n, int axis, double axis_max,
                      double strip_mm) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const double a = axis == 0 ? pts[i].x_mm : pts[i].y_mm;
    if (a < axis_max - strip_mm) continue;
    const double o = axis == 0 ? pts[i].y_mm : pts[i].x_mm;
    lo = std::min(lo, o);
    hi = std::max(hi, o);
  }
  return hi >= lo ? hi - lo : 0.0;
}

// One formula for every distance so the two passes (statistics, then the
// keep test) see the same bits.
double dist_mm(const XY &q, double cx, double cy) {
  const double dx = q.x_mm - cx;
  const double dy = q.y_mm - cy;
  return std::sqrt(dx * dx + dy * dy);
}

// Quantile q of v[0..m) by linear interpolation (h = q (m - 1)); reorders v.
double quantile(double *v, size_t m, double q) {
  q = std::min(std::max(q, 0.0), 1.0);
  const double h = q * static_cast<double>(m - 1);
  const size_t lo = static_cast<size_t>(std::floor(h));
  std::nth_element(v, v + lo, v + m);  // in place, no allocation
  const double a = v[lo];
  if (lo + 1 >= m) return a;
  const double b = *std::min_element(v + lo + 1, v + m);
  return a + (h - static_cast<double>(lo)) * (b - a);
}

bool in_window(double theta, const Params &p) {
  return theta >= p.crescent_angle_min_rad && theta <= p.crescent_angle_max_rad;
}

bool in_band(double d, const Info &info) {
  return d >= info.r_low_mm && d <= info.r_high_mm;
}

// Nothing is removed: the band is everything.
void band_all(Info *info) {
  info->r_low_mm = 0.0;
  info->r_high_mm = std::numeric_limits<double>::infinity();
}

// Near-circular: bounding-box centre, r_base = quantile (max by default).
void fit_circle_band(const XY *pts, size_t n, const Params &p, double *scratch,
                     size_t scratch_cap, Info *info) {
  const Box b = bounding_box(pts, n);
  info->center_x_mm = 0.5 * (b.x_min + b.x_max);
  info->center_y_mm = 0.5 * (b.y_min + b.y_max);
  if (p.circle_rbase_quantile >= 1.0) {
    double r = 0.0;
    for (size_t i = 0; i < n; ++i)
      r = std::max(r, dist_mm(pts[i], info->center_x_mm, info->center_y_mm));
    info->r_base_mm = r;
  } else {
    if (scratch == nullptr || scratch_cap < n) {
      info->r_base_mm = 0.0;
      band_all(info);
      return;
    }
    for (size_t i = 0; i < n; ++i)
      scratch[i] = dist_mm(pts[i], info->center_x_mm, info->center_y_mm);
    info->r_base_mm = quantile(scratch, n, p.circle_rbase_quantile);
  }
  info->r_low_mm = info->r_base_mm - p.circle_band_mm;
  info->r_high_mm = info->r_base_mm + p.circle_band_mm;
}

// Crescent: centroid, radius quantiles of the points inside the angle window.
void fit_crescent_band(const XY *pts, size_t n, const Params &p, double *scratch,
                       size_t scratch_cap, Info *info) {
  double sx = 0.0, sy = 0.0;
  for (size_t i = 0; i < n; ++i) {
    sx += pts[i].x_mm;
    sy += pts[i].y_mm;
  }
  info->center_x_mm = sx / static_cast<double>(n);
  info->center_y_mm = sy / static_cast<double>(n);
  if (scratch == nullptr || scratch_cap < n) {
    info->r_base_mm = 0.0;
    band_all(info);
    return;
  }
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    const double dx = pts[i].x_mm - info->center_x_mm;
    const double dy = pts[i].y_mm - info->center_y_mm;
    if (in_window(angle_pi(dy, dx), p))
      scratch[m++] = dist_mm(pts[i], info->center_x_mm, info->center_y_mm);
  }
  if (m == 0) {  // empty window: no point can satisfy the angle constraint
    info->r_base_mm = 0.0;
    info->r_low_mm = 1.0;
    info->r_high_mm = 0.0;  // empty band
    return;
  }
  // Low quantile first: quantile() reorders the buffer, but the multiset of
  // values stays the same, so the second call is still exact.
  const double d_low = quantile(scratch, m, p.crescent_q_low);
  const double d_up = quantile(scratch, m, p.crescent_q_high);
  info->r_base_mm = d_up;
  info->r_low_mm = d_low - p.crescent_relax_mm;
  info->r_high_mm = d_up + p.crescent_relax_mm;
}

// Keeps the points inside the band (and the angle window for a crescent),
// compacted to the front in their current (canonical) order.
size_t compact_band(XY *pts, size_t n, const Params &p, const Info &info) {
  const bool use_angle = info.shape == Shape::Crescent;
  size_t w = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!in_band(dist_mm(pts[i], info.center_x_mm, info.center_y_mm), info)) continue;
    if (use_angle) {
      const double theta = angle_pi(pts[i].y_mm - info.center_y_mm,
                                    pts[i].x_mm - info.center_x_mm);
      if (!in_window(theta, p)) continue;
    }
    pts[w++] = pts[i];
  }
  return w;
}

}  // namespace

Morphology measure_morphology(const XY *pts, size_t n, const Params &p) {
  Morphology m{0, 0, 0, 0, 0};
  if (pts == nullptr || n == 0) return m;
  const Box b = bounding_box(pts, n);
  m.x_range_mm = b.x_max - b.x_min;
  m.y_range_mm = b.y_max - b.y_min;
  m.elongation_mm = std::fabs(m.x_range_mm - m.y_range_mm);
  m.dy_x_mm = cross_range_mm(pts, n, 0, b.x_max, p.cross_strip_mm);
  m.dx_y_mm = cross_range_mm(pts, n, 1, b.y_max, p.cross_strip_mm);
  return m;
}

Shape classify(const Morphology &m, const Params &p) {
  const bool crescent = m.elongation_mm > p.crescent_range_mm ||
                        m.dy_x_mm > p.crescent_cross_mm ||
                        m.dx_y_mm > p.crescent_cross_mm;
  return crescent ? Shape::Crescent : Shape::NearCircular;
}

size_t cluster_layer(XY *pts, size_t n, const Params &p, double *scratch,
                     size_t scratch_cap, Info *info) {
  Info local;
  Info *out = info != nullptr ? info : &local;
  *out = Info{};
  if (pts == nullptr || n == 0) return 0;
  n = thinning::canonicalize(pts, n);
  if (n == 0) return 0;
  out->shape = classify(measure_morphology(pts, n, p), p);
  if (out->shape == Shape::NearCircular)
    fit_circle_band(pts, n, p, scratch, scratch_cap, out);
  else
    fit_crescent_band(pts, n, p, scratch, scratch_cap, out);
  return compact_band(pts, n, p, *out);
}

}  // namespace clustering
}  // namespace pv
