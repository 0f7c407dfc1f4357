// estimate() and finish(): from the bins to a volume, stage by stage.
//
//  1. final levelling transform from the order-independent sample
//  2. every stored point re-assigned to its final layer (counting sort)
//  3. rim height: ground peak, else the wall top
//  4. per usable layer: adaptive thinning -> clustering -> area fit
//  5. MAD cleanup of the area sequence
//  6. Simpson + frustum between the exact limits 0 and the rim
#include <algorithm>
#include <cmath>
#include <cstring>

#include "clustering/clustering.h"
#include "common/divisor.h"
#include "common/point_hash.h"
#include "rim/rim.h"
#include "session/session_impl.h"

namespace pv::session {

namespace {

// Layers closer than this to the bottom plane or to the rim hold points of
// the floor or the ground, not of the wall contour; their area comes from
// the extrapolation of the wall layers next to them (volume::Limits).
constexpr double kEndGuardMm = 1.5;
// A contour needs this many points after clustering to be fitted.
constexpr uint32_t kMinContourPoints = 32;
constexpr uint32_t kMinUsableLayers = 12;
constexpr uint64_t kMinPoints = 1000;
// Points above the depth range (when binned) beyond this share, per mille,
// mean the pit is deeper than the grid (measure(), below).
constexpr uint64_t kMaxAbovePerMille = 1;
// The widest band of wall, bottom to rim, that may lack a usable contour.
// Across a wider band the volume would rest on extrapolation, not on the
// scan: refuse instead (PV_ERR_WALL_GAP). 20 mm passes the bands that
// cleanup removes at sharp steps (protrusion faces) in the corpus.
constexpr double kMaxWallGapMm = 20.0;
// The most a volume may be of the largest kept section times the depth
// (PV_PIT_CHECK_SECTIONS): 1 for sections as measured, plus what the end
// extrapolation and the quadrature's noise may add. Corpus (paper and
// polar, standard and held-out sets): 0.20 to 0.998, the top from the
// nearly cylindrical shallow_wide scans, whose mean section is 0.998 of
// their largest.
constexpr double kMaxSectionsShare = 1.05;
// pv_layer_info_t.kept of a fitted layer before the cleanup decides.
constexpr uint8_t kUsablePending = 2;

pv_status_t final_transform(pv_session *s, levelling::Transform *t) {
  switch (fit_sample(s, t)) {
    case levelling::Status::Ok: return PV_OK;
    case levelling::Status::TooFewPoints: return PV_ERR_TOO_FEW_POINTS;
    case levelling::Status::NoPlane: return PV_ERR_NO_BOTTOM_PLANE;
  }
  return PV_ERR_INTERNAL;
}

// Counting sort of all stored points by final layer into s->order.
// Returns the number of stored points outside the grid under t.
uint64_t assign_layers(pv_session *s, const levelling::Transform &t) {
  const uint32_t L = s->grid.layers;
  std::memset(s->layer_start, 0, (L + 1) * sizeof(uint32_t));
  std::fill(s->layer_weight, s->layer_weight + L, 0.0);
  uint64_t outside = 0;
  const uint32_t cap = s->bins.capacity();
  for (uint32_t b = 0; b < L; ++b) {
    const P3 *pts = s->bins.points(b);
    const double w = std::ldexp(1.0, s->bins.level(b));  // points each one stands for
    for (uint32_t i = 0; i < s->bins.count(b); ++i) {
      const int64_t j = s->grid.layer_of(t.level_z(pts[i]));
      if (j < 0) {
        ++outside;
        continue;
      }
      ++s->layer_start[j + 1];
      s->layer_weight[j] += w;
    }
  }
  for (uint32_t j = 0; j < L; ++j) s->layer_start[j + 1] += s->layer_start[j];
  // Method surface reads the points from the bins, not layer by layer: it
  // has no order array (session.cpp, layout()).
  if (s->order == nullptr) return outside;
  // Second pass places slot ids; layer_start[j] advances to the end of j,
  // so shift back afterwards.
  for (uint32_t b = 0; b < L; ++b) {
    const P3 *pts = s->bins.points(b);
    for (uint32_t i = 0; i < s->bins.count(b); ++i) {
      const int64_t j = s->grid.layer_of(t.level_z(pts[i]));
      if (j >= 0) s->order[s->layer_start[j]++] = b * cap + i;
    }
  }
  for (uint32_t j = L; j > 0; --j) s->layer_start[j] = s->layer_start[j - 1];
  s->layer_start[0] = 0;
  return outside;
}

// The number of stored points outside the grid under t, as assign_layers()
// counts them (the same layer_of() test on the same level_z()), for method
// surface, which needs nothing else of the final layers when its rim comes
// from the ground ring or the rim plane: a fifth of the cost of the two
// per-layer sums. layer_of(z) is outside exactly when
// z / layer_mm + 0.5 is not in [-below, layers - below) (floor of a value
// against an integer bound); Divisor: the same bits as the division.
uint64_t count_outside(const pv_session *s, const levelling::Transform &t) {
  const gridding::Grid &g = s->grid;
  const double lo = -double(g.below), hi = double(g.layers - g.below);
  const Divisor per_layer(g.layer_mm);
  uint64_t outside = 0;
  for (uint32_t b = 0; b < g.layers; ++b) {
    const P3 *pts = s->bins.points(b);
    const uint32_t n = s->bins.count(b);
    for (uint32_t i = 0; i < n; ++i) {
      const double z = t.level_z(pts[i]);
      const double v = per_layer.of(z) + 0.5;
      outside += (v >= lo && v < hi) ? 0 : 1;
    }
  }
  return outside;
}

// Levelled XY of the points of final layer j, at most the work capacity.
// A layer with more points keeps those passing the lowest sufficient hash
// level: a deterministic, order-independent subset.
size_t gather_layer(pv_session *s, const levelling::Transform &t, uint32_t j) {
  const uint32_t from = s->layer_start[j], to = s->layer_start[j + 1];
  const size_t cap = layer_work_capacity(s->cfg);
  const P3 *slots = s->bins.points(0);  // order[] holds global slot ids
  uint8_t level = 0;
  for (;; ++level) {
    size_t n = 0;
    for (uint32_t q = from; q < to; ++q) {
      const P3 &p = slots[s->order[q]];
      if (level > 0 && !binning::LayerBins::passes(point_hash(p), level)) continue;
      if (n == cap) break;
      const Eigen::Vector3d v = t.apply(p);
      s->layer_pts[n++] = XY{v.x(), v.y()};
    }
    if (n < cap || level == 63) return n;
  }
}

struct LayerOutcome {
  bool usable;
  double area_mm2;
  uint32_t points;
  uint8_t shape;
};

LayerOutcome process_layer(pv_session *s, size_t n) {
  LayerOutcome o{false, 0.0, 0, 0};
  thinning::Params tp;
  tp.knn_k = s->cfg.knn_k;
  tp.s0_mm = s->cfg.thin_base_mm;
  n = thinning::thin_layer(s->layer_pts, n, tp, s->thin_ws);

  if (s->cfg.method == PV_METHOD_POLAR) {
    // The trimmed periodic fit does its own outlier rejection (see
    // area/polar_area.h), in place of the paper's clustering bands.
    area::PolarResult pr;
    if (n < kMinContourPoints ||
        !area::polar_area(s->layer_pts, n, area::PolarParams{}, s->polar_scratch,
                          s->polar_scratch_cap, &pr)) {
      o.points = uint32_t(n);
      return o;
    }
    o.points = pr.points_used;
    o.area_mm2 = pr.area_mm2;
    o.usable = true;
    return o;
  }

  clustering::Params cp;
  cp.crescent_range_mm = s->cfg.crescent_range_mm;
  cp.crescent_cross_mm = s->cfg.crescent_cross_mm;
  cp.circle_band_mm = s->cfg.circle_band_mm;
  cp.crescent_relax_mm = s->cfg.crescent_relax_mm;
  clustering::Info info;
  n = clustering::cluster_layer(s->layer_pts, n, cp, s->cluster_scratch, s->cluster_scratch_cap,
                                &info);
  o.shape = uint8_t(info.shape);
  o.points = uint32_t(n);
  if (n < kMinContourPoints) return o;

  area::Result ar;
  if (!area::fit_area(s->layer_pts, n, area::Params{}, s->area_scratch, s->area_scratch_cap, &ar)) {
    return o;
  }
  o.usable = std::isfinite(ar.area_mm2);
  o.area_mm2 = ar.area_mm2;
  return o;
}

// The most the pit's volume can be, mm3, from the levelled sample: the
// cylinder around its points (99 % of them by radius from their centre,
// 99 % by height). A scan in centimetres or metres stops here with
// PV_PIT_CHECK_TOO_SMALL: its rim and floor, ten or a thousand times
// small, fail the later stages with advice that does not say what to do.
// Only a pit's proportions qualify: a cylinder at least kMinDepthPerRadius
// as deep as wide (the widest, shallowest pits in the sweeps: 0.09 with
// their ground ring); a flat plate is not a small pit, it has no rim.
// Returns a negative bound for what is too flat to be a pit.
constexpr double kMinDepthPerRadius = 0.03;
double volume_bound_mm3(pv_session *s, const levelling::Transform &t) {
  const uint32_t n = s->sample.size();
  if (n < 16) return -1.0;
  double cx = 0.0, cy = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    s->lv.a[i] = t.apply(s->sample_points[i]);
    cx += s->lv.a[i].x();
    cy += s->lv.a[i].y();
  }
  cx /= double(n);
  cy /= double(n);
  double *v = s->lv.v;
  const auto quantile = [v, n](double q) {
    const size_t k = size_t(q * double(n - 1));
    std::nth_element(v, v + k, v + n);
    return v[k];
  };
  for (uint32_t i = 0; i < n; ++i) v[i] = s->lv.a[i].z();
  const double z_lo = quantile(0.005), z_hi = quantile(0.995);
  for (uint32_t i = 0; i < n; ++i) {  // squared radii: no libm call, the same bits everywhere
    const double dx = s->lv.a[i].x() - cx, dy = s->lv.a[i].y() - cy;
    v[i] = dx * dx + dy * dy;
  }
  const double r2 = quantile(0.99), depth = z_hi - z_lo;
  if (depth * depth < kMinDepthPerRadius * kMinDepthPerRadius * r2) return -1.0;
  return 3.14159265358979323846 * r2 * depth;
}

// Coverage per height band for the per-layer methods: the share of a band's
// layers whose contour was usable and kept by the cleanup.
void layer_coverage(const pv_session *s, double rim_mm, pv_result_t *out) {
  uint32_t total[PV_COVERAGE_BANDS] = {}, seen[PV_COVERAGE_BANDS] = {};
  for (uint32_t i = 0; i < s->layer_info_count; ++i) {
    const pv_layer_info_t &li = s->layer_info[i];
    int b = int(double(li.z_mm) / rim_mm * PV_COVERAGE_BANDS);
    b = b < 0 ? 0 : (b >= PV_COVERAGE_BANDS ? PV_COVERAGE_BANDS - 1 : b);
    ++total[b];
    if (li.kept == 1) ++seen[b];
  }
  out->coverage_bands = PV_COVERAGE_BANDS;
  for (int b = 0; b < PV_COVERAGE_BANDS; ++b) {
    out->coverage[b] = total[b] ? float(seen[b]) / float(total[b]) : 0.0f;
  }
}

}  // namespace

// From frame t and its opening: the tilt, the rim (the opening's, else
// the top of the wall over the final layers) and the points outside the
// grid, into out. PV_OK, or the status that ends the measurement.
static pv_status_t rim_in_frame(pv_session *s, const levelling::Transform &t, const Opening &opening,
                                pv_result_t *out, double *rim_mm) {
  out->tilt_deg = t.tilt_deg();
  if (out->tilt_deg > 30.0 && out->tilt_deg < 150.0) out->warnings |= PV_WARN_LARGE_TILT;
  if (opening_missing(s, opening)) return PV_ERR_NO_RIM;
  const Rim lid = opening_rim(s, t, opening);
  *rim_mm = lid.mm;
  const bool have_rim = lid.found;
  // The final layers serve the per-layer methods and the wall top; method
  // surface with a rim needs only how many points fall outside them.
  const bool layers_needed = s->cfg.method != PV_METHOD_SURFACE || !have_rim;
  const uint64_t outside = layers_needed ? assign_layers(s, t) : count_outside(s, t);
  if (!have_rim) *rim_mm = rim::wall_top_mm(s->layer_weight, s->grid, s->seq_scratch);
  out->points_out_of_range = s->points_out_of_range + outside;
  out->points_stored = s->bins.stored() - outside;
  if (out->points_out_of_range * 100 > s->points_in) out->warnings |= PV_WARN_OUT_OF_RANGE;

  if (!(*rim_mm > 4 * kEndGuardMm)) return PV_ERR_NO_RIM;
  if (*rim_mm > s->grid.top_mm() - 2 * kEndGuardMm) return PV_ERR_DEPTH_EXCEEDS_CAPACITY;
  out->depth_mm = *rim_mm;
  return PV_OK;
}

// Method surface in frame t with its opening.
static pv_status_t surface_measure(pv_session *s, const levelling::Transform &t, const Opening &opening,
                                   pv_result_t *out) {
  double rim_mm = 0.0;
  s->weak_frame_leaned = false;
  const pv_status_t framed = rim_in_frame(s, t, opening, out, &rim_mm);
  if (framed != PV_OK) {
    out->status = framed;
    return framed;
  }
  return measure_surface(s, t, rim_mm, lid_shift_mm(s, t, opening), opening.floor, weak_opening(opening), out);
}

// The checks that refuse a frame as much as a pit: a floor-plane start
// 20-30 deg off a scan held 40-60 deg off (a rounded bowl, a pit without
// surround), or the right plane the wrong way up, finds an opening whose
// section is smaller than the pit's below it (NARROW_MOUTH), wall inside
// the void (POINTS_INSIDE) or an opening facing away (OPENING_TILT). And a
// rim above the grid's top (DEPTH_EXCEEDS_CAPACITY from rim_in_frame): a
// 1.1 m shallow pit without surround held 46 deg off found no opening from
// the floor plane or the axis; two turned starts found a "ground" along
// its side, taken first, the rim 1123 mm (its width) over its bottom
// (seed 1324 #499). measure()'s own depth check, on the points above the
// grid at push, still follows whichever frame measures.
constexpr pv_pit_check_t kRetriedChecks[] = {PV_PIT_CHECK_NARROW_MOUTH, PV_PIT_CHECK_POINTS_INSIDE,
                                             PV_PIT_CHECK_OPENING_TILT};
static bool frame_refused(const pv_result_t &r) {
  if (r.status == PV_ERR_DEPTH_EXCEEDS_CAPACITY) return true;
  if (r.status != PV_ERR_NOT_A_PIT) return false;
  for (pv_pit_check_t c : kRetriedChecks) {
    if (r.failed_check == uint32_t(c)) return true;
  }
  return false;
}
// A frame from a later start within this of the refused one is the same
// frame: the refusal was the pit's (a doubled scan's upper copy inside the
// void), not the frame's. Measured on tuning seeds 1311-1314 (399 tilted
// scans, 80 slips): the axis frames of scans refused for the frame lay
// 80-180 deg from the refused ones, those of slips refused for their
// copies within 0.2 deg (one at 11 deg), and one of those slips measured
// from it -1.5 % outside its interval (1314 #021).
constexpr double kMinFrameTurnCos = 0.86602540378443865;  // cos 30 deg

// A frame levelled on a ground and refused PV_ERR_NO_RIM for the wall
// going on above it all round (build_and_check, wall_above_sectors): a
// "ground" under the pit's top, a protrusion's top or a groove's ledge
// taken for the ground of a pit without surround. The opening is then
// looked for from the same start without grounds (the rim plane, the
// support plane). Tuning seeds 1334 #079 (a grooved bowl, its "ground"
// 17 mm under the rim) and 1335 #281 (a protrusion pit, 61 mm), fresh
// seed 1339 #509 (a protrusion pit scanned over an arc, 11 mm).
static bool ground_under_top(pv_status_t st, const Opening &o) {
  return st == PV_ERR_NO_RIM && o.found && on_ground(o);
}
// Levels from `from` without grounds and measures there: true with *t the
// frame where that passes every check; else false, the grounds allowed
// again (and *out to be reset by the caller).
static bool measured_without_grounds(pv_session *s, const levelling::Transform &floor_frame, SurfaceStart from,
                                     const pv_result_t &before, levelling::Transform *t, pv_result_t *out) {
  levelling::Transform next = floor_frame;
  load_sample(s);
  s->surface_no_ground = 1;
  const Opening o = level_for_surface(s, &next, from);
  if (o.found) {
    *out = before;
    if (surface_measure(s, next, o, out) == PV_OK) {
      *t = next;
      return true;
    }
  }
  s->surface_no_ground = 0;
  return false;
}

// Method surface from the floor-plane start, and from the later starts
// (level_surface.cpp: the scanner's axis, then that axis turned) where the
// frame was refused (kRetriedChecks) and a later start gives another
// (kMinFrameTurnCos); a first frame from the turned axis (grounds first)
// is retried there (the plane most starts agree on). A frame on a ground
// under the pit's top is levelled again from its start without grounds
// (ground_under_top). Each frame is held to the same checks; where all
// are refused, the first frame's refusal stands. The session's scratch
// (the model, the layer detail) holds the frame whose result is given:
// the first is measured again then. The model overlays the levelling's
// sample (session.cpp, layout()): it is loaded again before each
// levelling.
static pv_status_t surface_in_frame(pv_session *s, levelling::Transform *t, pv_result_t *out) {
  const levelling::Transform floor_frame = *t;
  const pv_result_t before = *out;
  s->surface_start = uint8_t(SurfaceStart::floor_plane);
  s->surface_no_ground = 0;
  const Opening opening = level_for_surface(s, t, SurfaceStart::floor_plane);
  const pv_status_t st = surface_measure(s, *t, opening, out);
  // The first frame's (the levelling without grounds below measures
  // another frame and sets the flag anew).
  const bool leaned = s->weak_frame_leaned;
  bool measured_again = false;
  if (ground_under_top(st, opening)) {
    if (measured_without_grounds(s, floor_frame, SurfaceStart::floor_plane, before, t, out)) return PV_OK;
    measured_again = true;
  } else if (st == PV_OK || !(frame_refused(*out) || leaned)) {
    return st;
  }
  const Eigen::Vector3d first_up = t->R.row(2);
  // A frame refused for its lean is wrong itself: any other frame is
  // worth measuring. Fresh seeds 1343 #697 and 1344 #785 (rounded bowls,
  // their support planes 27 and 9 deg off): the turned axis found the
  // ground and the lip, +0.08 % and +0.01 %.
  const double same_frame_cos = leaned ? kAgreeCos : kMinFrameTurnCos;
  const int turned = int(SurfaceStart::turned_axis);
  for (int from = std::min(int(opening.start) + 1, turned); from <= turned; ++from) {
    levelling::Transform next = floor_frame;
    load_sample(s);
    const Opening o = level_for_surface(s, &next, SurfaceStart(from));
    if (!o.found) break;  // nor from any later start (level_for_surface goes on to them)
    const uint8_t asked = uint8_t(from);
    from = int(o.start);  // the starts before it found nothing
    if (Eigen::Vector3d(next.R.row(2)).dot(first_up) > same_frame_cos) continue;
    *out = before;
    measured_again = true;
    const pv_status_t again = surface_measure(s, next, o, out);
    if (again == PV_OK ||
        (ground_under_top(again, o) && measured_without_grounds(s, floor_frame, SurfaceStart(asked), before, &next, out))) {
      *t = next;
      s->surface_start = asked;
      return PV_OK;
    }
  }
  if (!measured_again) return st;
  *out = before;
  load_sample(s);
  *t = floor_frame;
  return surface_measure(s, *t, level_for_surface(s, t, SurfaceStart::floor_plane), out);
}

static pv_status_t measure_stored(pv_session *s, pv_result_t *out, levelling::Transform *frame) {
  std::memset(out, 0, sizeof *out);
  establish_transform(s);
  out->points_in = s->points_in;
  out->points_invalid = s->points_invalid;
  s->layer_info_count = 0;
  if (s->points_invalid > 0) out->warnings |= PV_WARN_INVALID_POINTS;
  if (s->bins.thinned() > 0) out->warnings |= PV_WARN_POINTS_THINNED;

  auto fail = [out](pv_status_t st) {
    out->status = st;
    return st;
  };
  if (s->points_in - s->points_invalid < kMinPoints) return fail(PV_ERR_TOO_FEW_POINTS);

  levelling::Transform &t = *frame;
  const pv_status_t st = final_transform(s, &t);
  if (st != PV_OK) return fail(st);
  out->tilt_deg = t.tilt_deg();
  const double bound_cm3 = volume_bound_mm3(s, t) / 1000.0;
  if (bound_cm3 >= 0.0 && bound_cm3 < kMinVolumeCm3) {
    out->failed_check = PV_PIT_CHECK_TOO_SMALL;
    out->check_value = bound_cm3;
    out->check_limit = kMinVolumeCm3;
    return fail(PV_ERR_NOT_A_PIT);
  }

  // Method surface levels on the plane of the opening (level_surface.cpp).
  if (s->cfg.method == PV_METHOD_SURFACE) return surface_in_frame(s, &t, out);
  double rim_mm = 0.0;
  const pv_status_t framed = rim_in_frame(s, t, Opening{}, out, &rim_mm);
  if (framed != PV_OK) return fail(framed);

  // Per-layer areas of the usable band [guard, rim - guard].
  size_t m = 0;
  uint32_t unusable = 0;
  uint64_t used_points = 0;
  for (uint32_t j = 0; j < s->grid.layers; ++j) {
    const double z = s->grid.z_of(j);
    if (z < kEndGuardMm || z > rim_mm - kEndGuardMm) continue;
    const size_t n = gather_layer(s, t, j);
    const LayerOutcome o = process_layer(s, n);
    pv_layer_info_t &li = s->layer_info[s->layer_info_count++];
    // kept: 0 unusable; usable layers are marked after the cleanup below.
    li = pv_layer_info_t{float(z), float(o.area_mm2), o.points, 0, o.shape};
    if (!o.usable) {
      ++unusable;
      continue;
    }
    li.kept = kUsablePending;
    s->seq_z[m] = z;
    s->seq_area[m] = o.area_mm2;
    ++m;
    used_points += o.points;
  }
  if (unusable * 10 > s->layer_info_count) out->warnings |= PV_WARN_SPARSE_LAYERS;

  cleanup::Params mp;
  mp.window_early = s->cfg.mad_window_early;
  mp.window_late = s->cfg.mad_window_late;
  mp.k_early = s->cfg.mad_k_early;
  mp.k_late = s->cfg.mad_k_late;
  mp.split_mm = s->cfg.mad_split_mm;
  const size_t kept = m == 0 ? 0 : cleanup::mad_filter(s->seq_z, s->seq_area, m, mp, s->seq_keep,
                                                       s->seq_scratch, s->seq_scratch_cap);
  // Compact the kept layers in place and mark them in the layer detail.
  size_t w = 0;
  for (size_t i = 0; i < m; ++i) {
    if (!s->seq_keep[i]) continue;
    s->seq_z[w] = s->seq_z[i];
    s->seq_area[w] = s->seq_area[i];
    ++w;
  }
  // The usable layers are the sequence, in order: their cleanup verdicts
  // follow one to one.
  for (uint32_t i = 0, q = 0; i < s->layer_info_count; ++i) {
    if (s->layer_info[i].kept == kUsablePending) s->layer_info[i].kept = s->seq_keep[q++];
  }
  layer_coverage(s, rim_mm, out);
  out->layers_used = uint32_t(kept);
  out->layers_rejected = uint32_t(s->layer_info_count - kept);
  out->points_used = used_points;
  if ((m - kept) * 20 > m) out->warnings |= PV_WARN_LAYERS_REJECTED;
  if (kept < kMinUsableLayers) return fail(PV_ERR_TOO_FEW_LAYERS);
  double gap_from = 0.0, gap_to = s->seq_z[0];
  for (size_t i = 1; i <= kept; ++i) {
    const double lo = s->seq_z[i - 1], hi = i < kept ? s->seq_z[i] : rim_mm;
    if (hi - lo > gap_to - gap_from) {
      gap_from = lo;
      gap_to = hi;
    }
  }
  if (gap_to - gap_from > kMaxWallGapMm) {
    out->gap_from_mm = gap_from;
    out->gap_to_mm = gap_to;
    return fail(PV_ERR_WALL_GAP);
  }

  volume::Limits lim;
  lim.z_bottom_mm = 0.0;
  lim.z_rim_mm = rim_mm;
  double v_mm3 = 0;
  if (!volume::volume_between_mm3(s->seq_z, s->seq_area, kept, lim, s->seq_scratch,
                                  s->seq_scratch_cap, &v_mm3)) {
    return fail(PV_ERR_INTERNAL);
  }
  // Sections between 0 and the largest kept one bound the volume to
  // [0, largest x depth]; the quadrature's weights turn negative where
  // cleanup left uneven spacing (volume.h, V1), so an erratic sequence
  // (sections jumping 50-fold from layer to layer: a fuzz_session finding)
  // can integrate to a negative or impossible volume. Refuse it.
  double max_section = 0.0;
  for (size_t i = 0; i < kept; ++i) max_section = std::max(max_section, s->seq_area[i]);
  const double bound_mm3 = max_section * (rim_mm - lim.z_bottom_mm);
  const double share = bound_mm3 > 0.0 ? v_mm3 / bound_mm3 : 0.0;
  if (!(v_mm3 > 0.0) || !(share <= kMaxSectionsShare)) {
    out->failed_check = PV_PIT_CHECK_SECTIONS;
    out->check_value = share;
    out->check_limit = kMaxSectionsShare;
    return fail(PV_ERR_NOT_A_PIT);
  }
  // One open pit? Method surface's checks on the same points, last: the
  // model overlays the per-layer stages' scratch, and its sections replace
  // the area sequence.
  const double rim_area_mm2 = s->seq_area[kept - 1];
  const pv_status_t shape = check_pit_shape(s, t, rim_mm, out);
  if (shape != PV_OK) return fail(shape);
  out->volume_cm3 = v_mm3 / 1000.0;
  out->rim_area_mm2 = rim_area_mm2;
  out->status = PV_OK;
  return PV_OK;
}

// Whether the top of the grid the points were last binned with runs
// across the pit's top (its up within 45 deg of the pit's) or down its
// side. Only a cap can pass for the rim: a pit deeper than the grid then
// reads the cut as its rim. A cut down the side takes wall, which the
// surface model counts as unseen (bridged within the interval, or
// refused WALL_GAP), at its true height. The last provisional frame of a
// wide pit without ground can lie on its wall: a 1 m tapered pit 662 mm
// deep was binned 81 deg off from 524k points on, a 1.2 m container 85
// deg off, and the far wall beyond that frame's top (1.3 %, 9 % of their
// points) refused them for a depth they do not have; both measure inside
// their intervals.
constexpr double kCapCos = 0.70710678118654752;  // cos 45 deg
static bool grid_caps_the_pit(const gridding::LayerMap &m, const levelling::Transform &t) {
  const double n2 = m.a * m.a + m.b * m.b + m.c * m.c;
  const double up = m.a * t.R(2, 0) + m.b * t.R(2, 1) + m.c * t.R(2, 2);
  // up / sqrt(n2) >= cos 45, without a square root.
  return up > 0.0 && up * up >= kCapCos * kCapCos * n2;
}

// A pit deeper than the grid loses its top at push: the rim then found
// is the cut (a rounded bowl 923 mm deep, levelled 7 deg off, read -9 %
// with PV_OK: 0.48 % of its points above the grid). Far strays put at most
// 0.014 % of a scan there (sweep seed 1, 300 scans). Counted among the
// points binned with the provisional frame that stands (session.cpp,
// refine()): a frame that moved away was no measure of the pit. Held
// against what would be a volume only: a cloud that is no pit says so
// first.
pv_status_t measure(pv_session *s, pv_result_t *out) {
  levelling::Transform t;
  const pv_status_t st = measure_stored(s, out, &t);
  const uint64_t binned = s->points_accepted - s->points_before_frame;
  if (st != PV_OK || s->points_above_range * 1000 <= binned * kMaxAbovePerMille) return st;
  if (!grid_caps_the_pit(s->provisional_map, t)) return st;
  out->volume_cm3 = out->interval_cm3 = 0.0;
  out->status = PV_ERR_DEPTH_EXCEEDS_CAPACITY;
  return out->status;
}

}  // namespace pv::session
