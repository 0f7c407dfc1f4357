// pv_session_transform(): the levelling transform and the rim height that
// measure() uses, for host tools that measure the same levelled cloud with
// another method (host_tools/peers). It repeats measure()'s stages 1 and 3
// (final fit on the canonical sample; method surface: re-levelled on the
// plane of the opening, level_for_surface(); rim from that plane, else the
// ground peak, else the wall top over the per-layer
// weights; the lid, as depth_mm, where the rim plane's points put it)
// rather than caching them in the session,
// so the session layout does not change for a query tool. Keep it in step
// with measure.cpp (test_transform_query checks they agree).
#include <cmath>
#include <cstring>
#include <new>

#include "rim/rim.h"
#include "session/session_impl.h"

namespace pv::session {

namespace {

// Per final layer point weights under t, as assign_layers() in measure.cpp
// counts them (each stored point stands for 2^level points of its bin).
void layer_weights(pv_session *s, const levelling::Transform &t) {
  const uint32_t L = s->grid.layers;
  for (uint32_t j = 0; j < L; ++j) s->layer_weight[j] = 0.0;
  for (uint32_t b = 0; b < L; ++b) {
    const P3 *pts = s->bins.points(b);
    const double w = std::ldexp(1.0, s->bins.level(b));
    for (uint32_t i = 0; i < s->bins.count(b); ++i) {
      const int64_t j = s->grid.layer_of(t.level_z(pts[i]));
      if (j >= 0) s->layer_weight[j] += w;
    }
  }
}

}  // namespace

pv_status_t transform_query(pv_session *s, pv_transform_t *out, double *model_rim_mm,
                            surface::FloorPlane *floor) {
  establish_transform(s);
  levelling::Transform t;
  switch (fit_sample(s, &t)) {
    case levelling::Status::Ok: break;
    case levelling::Status::TooFewPoints: return PV_ERR_TOO_FEW_POINTS;
    case levelling::Status::NoPlane: return PV_ERR_NO_BOTTOM_PLANE;
  }
  // As measure(): method surface re-levels (ground ring, else rim plane)
  // before the layers are assigned, from the start the last measure() took.
  Opening opening;
  if (s->cfg.method == PV_METHOD_SURFACE) opening = level_for_surface(s, &t, SurfaceStart(s->surface_start));
  if (floor != nullptr) *floor = opening.floor;
  layer_weights(s, t);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out->rotation[3 * r + c] = t.R(r, c);
    out->translation_mm[r] = t.t(r);
  }
  // As measure(): the opening's rim, else the wall's top.
  const Rim lid = opening_rim(s, t, opening);
  out->rim_from_ground = lid.from_ground ? 1u : 0u;
  *model_rim_mm = lid.found ? lid.mm : rim::wall_top_mm(s->layer_weight, s->grid, s->seq_scratch);
  out->rim_mm = lid.found ? lid.mm + lid_shift_mm(s, t, opening) : *model_rim_mm;  // as depth_mm
  if (!(*model_rim_mm > 0.0) || opening_missing(s, opening)) {
    out->rim_mm = -1.0;
    return PV_ERR_NO_RIM;
  }
  return PV_OK;
}

}  // namespace pv::session

extern "C" pv_status_t pv_session_transform(pv_session_t *s, pv_transform_t *out) {
  if (s == nullptr || out == nullptr) return PV_ERR_INVALID_ARGUMENT;
  std::memset(out, 0, sizeof *out);
  double model_rim_mm = 0.0;
#if defined(__cpp_exceptions)  // as pv_session_finish: nothing escapes the ABI
  try {
    return pv::session::transform_query(s, out, &model_rim_mm);
  } catch (const std::bad_alloc &) {
    return PV_ERR_OUT_OF_MEMORY;
  } catch (...) {
    return PV_ERR_INTERNAL;
  }
#else
  return pv::session::transform_query(s, out, &model_rim_mm);
#endif
}
