// measure() for method surface: the stored points, levelled, build one
// surface model of the pit (core/surface), whose exact integral below the
// rim is the volume; the unseen wall it had to bridge gives the interval
// and the coverage.
#include <algorithm>
#include <cmath>

#include "session/session_impl.h"

namespace pv::session {

namespace {

// Above this share of the volume resting on bridged (unseen) wall, the
// scan cannot support a number (docs/method.md, measured on the corpus).
constexpr double kMaxUnseenShare = 0.30;
// Relative part of the interval for what bridging does not cover: the
// levelling, the fit of seen bins (docs/method.md).
constexpr double kBaseRelInterval = 0.0010;
// Uncertainty of the rim height, mm, times the rim section.
constexpr double kRimSigmaMm = 0.3;

struct Levelled {
  const pv_session *s;
  const levelling::Transform *t;
};

void visit_points(void *ctx, surface::PointFn fn, void *fn_ctx) {
  const auto *lv = static_cast<const Levelled *>(ctx);
  const binning::LayerBins &bins = lv->s->bins;
  for (uint32_t b = 0; b < bins.layers(); ++b) {
    const P3 *pts = bins.points(b);
    for (uint32_t i = 0; i < bins.count(b); ++i) {
      const Eigen::Vector3d v = lv->t->apply(pts[i]);
      fn(fn_ctx, surface::Point{v.x(), v.y(), v.z()});
    }
  }
}

// The widest run of height bands seen on less than half their wall.
void widest_unseen_band(const pv_result_t &r, double rim_mm, double *from, double *to) {
  *from = *to = 0;
  const double h = rim_mm / r.coverage_bands;
  uint32_t best = 0;
  for (uint32_t b = 0; b < r.coverage_bands;) {
    if (r.coverage[b] >= 0.5f) {
      ++b;
      continue;
    }
    uint32_t e = b;
    while (e < r.coverage_bands && r.coverage[e] < 0.5f) ++e;
    if (e - b > best) {
      best = e - b;
      *from = b * h;
      *to = e * h;
    }
    b = e;
  }
}

}  // namespace

pv_status_t measure_surface(pv_session *s, const levelling::Transform &t, double rim_mm,
                            pv_result_t *out) {
  const surface::Params p;
  Levelled lv{s, &t};
  const surface::PointSource src{&lv, visit_points};
  surface::Model m;
  const double z_bottom = s->grid.z_of(0) - 0.5 * s->grid.layer_mm;
  const surface::Status st = surface::build(src, z_bottom, rim_mm, p, s->surf, &m);
  if (st == surface::Status::TooFewPoints) {
    out->status = PV_ERR_TOO_FEW_POINTS;
    return out->status;
  }
  if (st != surface::Status::Ok) {
    out->status = PV_ERR_TOO_FEW_LAYERS;
    return out->status;
  }
  const surface::Volume v = surface::integrate(s->surf, m, p);
  out->coverage_bands = PV_COVERAGE_BANDS;
  surface::coverage(s->surf, m, p, PV_COVERAGE_BANDS, out->coverage);
  out->points_used = s->bins.stored();
  out->layers_used = m.seen_bins;
  out->layers_rejected = m.rejected_bins;
  out->rim_area_mm2 = v.rim_area_mm2;
  out->unseen_share = v.volume_mm3 > 0 ? v.unseen_mm3 / v.volume_mm3 : 1.0;
  if (m.bridged_bins > 0) out->warnings |= PV_WARN_BRIDGED;
  if (!(v.volume_mm3 > 0) || !std::isfinite(v.volume_mm3)) {
    out->status = PV_ERR_TOO_FEW_LAYERS;
    return out->status;
  }
  if (out->unseen_share > kMaxUnseenShare) {
    widest_unseen_band(*out, rim_mm, &out->gap_from_mm, &out->gap_to_mm);
    out->status = PV_ERR_WALL_GAP;
    return out->status;
  }
  const double bridge = std::max(v.hi_mm3 - v.volume_mm3, v.volume_mm3 - v.lo_mm3);
  const double interval_mm3 =
      bridge + kBaseRelInterval * v.volume_mm3 + kRimSigmaMm * v.rim_area_mm2;
  out->volume_cm3 = v.volume_mm3 / 1000.0;
  out->interval_cm3 = interval_mm3 / 1000.0;
  out->status = PV_OK;
  return PV_OK;
}

}  // namespace pv::session
