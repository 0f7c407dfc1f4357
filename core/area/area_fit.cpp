// Cross-section area of one layer: see area_fit.h for the method and the
// decisions D1..D7 referred to below.
#include "area/area_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "common/angle.h"

namespace pv {
namespace area {
namespace {

constexpr double kPi = 3.14159265358979323846;
// LDLT pivots below this fraction of the largest mean the piece's points do
// not determine that many coefficients (D6).
constexpr double kPivotFloor = 1e-10;

// Total order on points so that sorting makes the result independent of the
// input order (D7).
bool less_xy(const XY &a, const XY &b) {
  return a.x_mm < b.x_mm || (a.x_mm == b.x_mm && a.y_mm < b.y_mm);
}

struct Bounds {
  double x_min, x_max, y_min, y_max;
  XY left, right;  // x-extreme points, ties broken by y (total order, D7)
};

// Extremes of the layer; false on non-finite input (a NaN would otherwise
// poison every comparison silently).
bool layer_bounds(const XY *pts, size_t n, Bounds *b) {
  b->x_min = b->y_min = HUGE_VAL;  // double infinity (INFINITY is a float)
  b->x_max = b->y_max = -HUGE_VAL;
  if (n > 0) b->left = b->right = pts[0];
  for (size_t i = 0; i < n; ++i) {
    const double x = pts[i].x_mm, y = pts[i].y_mm;
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    b->x_min = std::min(b->x_min, x);
    b->x_max = std::max(b->x_max, x);
    b->y_min = std::min(b->y_min, y);
    b->y_max = std::max(b->y_max, y);
    if (less_xy(pts[i], b->left)) b->left = pts[i];
    if (less_xy(b->right, pts[i])) b->right = pts[i];
  }
  return true;
}

// One piece: breakpoint interval [x_lo, x_hi] and its points [first, first+count).
struct Piece {
  double x_lo, x_hi;
  size_t first, count;
};

// Splits the sorted half into the P cosine-spaced intervals (D1); returns the
// number of pieces written (always P).
uint32_t split_pieces(const XY *half, size_t m, const double *breaks, uint32_t P,
                      Piece *pieces) {
  size_t i = 0;
  for (uint32_t k = 0; k < P; ++k) {
    const size_t first = i;
    // The last piece takes everything left, including points at exactly x_max.
    if (k + 1 == P) {
      i = m;
    } else {
      while (i < m && half[i].x_mm < breaks[k + 1]) ++i;
    }
    pieces[k] = Piece{breaks[k], breaks[k + 1], first, i - first};
  }
  return P;
}

// Merges the thinnest piece into its thinner neighbour until every piece has
// min_pts points or only one is left (D2). Deterministic: smallest count
// first, lowest index on ties; left neighbour on ties.
uint32_t merge_thin(Piece *pieces, uint32_t np, size_t min_pts) {
  while (np > 1) {
    uint32_t worst = 0;
    for (uint32_t k = 1; k < np; ++k)
      if (pieces[k].count < pieces[worst].count) worst = k;
    if (pieces[worst].count >= min_pts) break;
    uint32_t left;  // merge pieces[left] and pieces[left + 1]
    if (worst == 0) {
      left = 0;
    } else if (worst + 1 == np) {
      left = worst - 1;
    } else {
      left = pieces[worst - 1].count <= pieces[worst + 1].count ? worst - 1 : worst;
    }
    pieces[left].x_hi = pieces[left + 1].x_hi;
    pieces[left].count += pieces[left + 1].count;
    for (uint32_t k = left + 1; k + 1 < np; ++k) pieces[k] = pieces[k + 1];
    --np;
  }
  return np;
}

// Solves the leading (D+1)x(D+1) block of the normal equations; false when a
// pivot is too small for that degree (D6).
template <int D>
bool solve_degree(const Eigen::Matrix4d &M, const Eigen::Vector4d &r, Eigen::Vector4d *a) {
  using Mat = Eigen::Matrix<double, D + 1, D + 1>;
  using Vec = Eigen::Matrix<double, D + 1, 1>;
  const Mat m = M.template topLeftCorner<D + 1, D + 1>();
  const Eigen::LDLT<Mat> ldlt(m);
  if (ldlt.info() != Eigen::Success) return false;
  const Vec d = ldlt.vectorD();
  const double dmax = d.cwiseAbs().maxCoeff();
  if (!(dmax > 0.0) || d.minCoeff() <= kPivotFloor * dmax) return false;
  const Vec sol = ldlt.solve(r.template head<D + 1>());
  a->setZero();
  a->template head<D + 1>() = sol;
  return true;
}

// A piece's fitted cubic over the x-span its own points support.
struct Fit {
  double xa, xb;      // supported span: first and last point of the piece
  double ya, yb;      // fitted y - y_mid at xa and xb
  double integral;    // of the fitted y - y_mid over [xa, xb]
  bool ok;
};

// Least-squares cubic over one piece in t = (x - xc)/hw (D5), integrated
// exactly over the span of the piece's points plus a short reach (D3): never
// extrapolated across an interval its points do not reach, where a cubic
// can run away (an occluded stretch of wall leaves such gaps).
Fit fit_piece(const XY *half, const Piece &pc, double y_mid) {
  Fit f{0, 0, 0, 0, 0, false};
  if (pc.count == 0) return f;
  const double xc = 0.5 * (pc.x_lo + pc.x_hi);
  const double hw = 0.5 * (pc.x_hi - pc.x_lo);
  if (!(hw > 0.0)) return f;
  // Normal equations X^T X a = X^T y accumulated as moments of t.
  double mom[7] = {0, 0, 0, 0, 0, 0, 0};
  Eigen::Vector4d r = Eigen::Vector4d::Zero();
  for (size_t i = pc.first; i < pc.first + pc.count; ++i) {
    const double t = (half[i].x_mm - xc) / hw;
    const double y = half[i].y_mm - y_mid;
    double tp = 1.0;
    for (int j = 0; j < 7; ++j) {
      if (j < 4) r[j] += tp * y;
      mom[j] += tp;
      tp *= t;
    }
  }
  Eigen::Matrix4d M;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) M(i, j) = mom[i + j];
  Eigen::Vector4d a;
  if (!solve_degree<3>(M, r, &a) && !solve_degree<2>(M, r, &a) && !solve_degree<1>(M, r, &a) &&
      !solve_degree<0>(M, r, &a))
    return f;
  const auto value = [&a](double t) { return a[0] + t * (a[1] + t * (a[2] + t * a[3])); };
  const auto primitive = [&a](double t) {
    return t * (a[0] + t * (a[1] / 2 + t * (a[2] / 3 + t * a[3] / 4)));
  };
  // The fit covers its whole interval when the strips its points leave
  // uncovered at either end are small (3 point spacings or 3 mm): there a
  // cubic follows a convex contour better than a chord. Across a wider
  // strip, a contour the scan did not see, it can run away: it stops two
  // spacings past its points and integrate_half() bridges the rest.
  const double x_first = half[pc.first].x_mm, x_last = half[pc.first + pc.count - 1].x_mm;
  const double spacing = (x_last - x_first) / double(pc.count > 1 ? pc.count - 1 : 1);
  const double small = std::max(3.0 * spacing, 3.0);
  f.xa = x_first - pc.x_lo <= small ? pc.x_lo : x_first - 2.0 * spacing;
  f.xb = pc.x_hi - x_last <= small ? pc.x_hi : x_last + 2.0 * spacing;
  const double ta = (f.xa - xc) / hw;
  const double tb = (f.xb - xc) / hw;
  f.ya = value(ta);
  f.yb = value(tb);
  f.integral = hw * (primitive(tb) - primitive(ta));  // dx/dt = hw
  f.ok = true;
  return f;
}

// Integral of one half's piecewise fit over [x_min, x_max]; pieces reported
// in *pieces_out.
double integrate_half(const XY *half, size_t m, const double *breaks, uint32_t P,
                      size_t min_pts, double y_mid, uint32_t *pieces_out) {
  Piece pieces[kMaxPieces];
  uint32_t np = split_pieces(half, m, breaks, P, pieces);
  np = merge_thin(pieces, np, min_pts);
  // Fitted spans, joined by chords across what no piece supports: the
  // small strips between pieces, and any stretch of contour the scan did
  // not see. A chord is the closure the points can vouch for.
  double s = 0.0;
  bool have_prev = false;
  double prev_x = 0.0, prev_y = 0.0;
  for (uint32_t k = 0; k < np; ++k) {
    const Fit f = fit_piece(half, pieces[k], y_mid);
    if (!f.ok) continue;
    if (have_prev) s += 0.5 * (prev_y + f.ya) * (f.xa - prev_x);
    s += f.integral;
    prev_x = f.xb;
    prev_y = f.yb;
    have_prev = true;
  }
  *pieces_out = np;
  return s;
}

}  // namespace

size_t scratch_needed(size_t n) { return 2 * n; }

bool fit_area(const XY *pts, size_t n, const Params &p, XY *scratch, size_t scratch_cap,
              Result *out) {
  if (pts == nullptr || out == nullptr || scratch == nullptr) return false;
  if (scratch_cap < scratch_needed(n)) return false;
  const size_t min_pts = std::max<size_t>(4, p.min_points_per_piece);
  if (n < min_pts) return false;
  Bounds b;
  if (!layer_bounds(pts, n, &b)) return false;
  if (!(b.x_max > b.x_min) || !(b.y_max > b.y_min)) return false;

  // Halves (D4): above / below the split line, the two x-extreme points in
  // both, plus an optional shared band.
  const double y_mid = 0.5 * (b.y_max + b.y_min);
  const double band = std::max(0.0, p.mid_band_ratio) * (b.y_max - b.y_min);
  const bool chord = p.split_through_extremes;
  const double slope = (b.right.y_mm - b.left.y_mm) / (b.right.x_mm - b.left.x_mm);
  XY *upper = scratch;
  XY *lower = scratch + n;
  size_t nu = 0, nl = 0;
  for (size_t i = 0; i < n; ++i) {
    const XY q = pts[i];
    const double y_split = chord ? b.left.y_mm + slope * (q.x_mm - b.left.x_mm) : y_mid;
    const bool end = (q.x_mm == b.x_min || q.x_mm == b.x_max);
    if (end || q.y_mm >= y_split - band) upper[nu++] = q;
    if (end || q.y_mm <= y_split + band) lower[nl++] = q;
  }
  if (nu < min_pts || nl < min_pts) return false;
  std::sort(upper, upper + nu, less_xy);
  std::sort(lower, lower + nl, less_xy);

  // Cosine-spaced breakpoints, ascending, ends pinned to the data extent (D1).
  // Sparse layers get fewer, wider pieces (D2): a cubic needs a good margin
  // over its 4 coefficients, or an end piece extrapolates wildly.
  const size_t per_piece = std::max<size_t>(min_pts, p.target_points_per_piece);
  const size_t by_density = std::max<size_t>(1, std::min(nu, nl) / per_piece);
  const uint32_t P = static_cast<uint32_t>(
      std::min<size_t>(by_density, std::min(kMaxPieces, std::max<uint32_t>(1, p.max_pieces))));
  double breaks[kMaxPieces + 1];
  const double cx = 0.5 * (b.x_max + b.x_min);
  const double R = 0.5 * (b.x_max - b.x_min);
  for (uint32_t k = 0; k <= P; ++k) {
    double s, c;  // no libm (common/angle.h): the same nodes on every target
    sin_cos(kPi * static_cast<double>(k) / static_cast<double>(P), &s, &c);
    breaks[k] = cx - R * c;
  }
  breaks[0] = b.x_min;
  breaks[P] = b.x_max;

  Result res;
  const double s_up = integrate_half(upper, nu, breaks, P, min_pts, y_mid, &res.pieces_upper);
  const double s_low = integrate_half(lower, nl, breaks, P, min_pts, y_mid, &res.pieces_lower);
  res.area_mm2 = std::fabs(s_up - s_low);
  // A closed contour through these points lies in their bounding box; an
  // area beyond it is a fit that ran away, not a measurement (D9).
  if (!(res.area_mm2 <= (b.x_max - b.x_min) * (b.y_max - b.y_min))) return false;
  *out = res;
  return true;
}

}  // namespace area
}  // namespace pv
