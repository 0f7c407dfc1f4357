// pv_session_wall_grid(): the surface model's wall grid of the last
// measurement, for plots and reports (pitvol measure --export, the scan
// report). Like transform_query.cpp it repeats measure()'s steps instead of
// keeping the model in the session (the layout stays as it is for a query
// tool): the transform and the rim of pv_session_transform(), then the
// same surface::build() on the same stored points and on the same grids
// (scaled for a pit wider than surface_max_radius_mm: the session keeps
// the scale, surface_scale_eighths), which is deterministic, so the grid
// is the one the volume was integrated over
// (test_wall_grid_query checks the coverage it gives against the result's).
//
// It reads only the model's public grids: wall_val and wall[].state, bin
// (t, z) at z * theta_bins + t (surface_model.h, Workspace).
#include <cstring>
#include <new>

#include "session/session_impl.h"

namespace pv::session {

namespace {

uint8_t public_state(const surface::WallBin &b, const surface::Params &p) {
  switch (b.state) {
    case surface::kSeen: return PV_WALL_SEEN;
    case surface::kFloorBin: return PV_WALL_FLOOR;
    case surface::kBridged: return b.gap <= p.short_gap_bins ? PV_WALL_SHORT_BRIDGE : PV_WALL_UNSEEN;
    default: return PV_WALL_NONE;
  }
}

pv_status_t query(pv_session *s, pv_wall_grid_t *grid, float *radius_mm, uint8_t *state,
                  size_t capacity) {
  if (s->cfg.method != PV_METHOD_SURFACE) return PV_ERR_WRONG_STATE;
  pv_transform_t tf;
  double model_rim_mm = 0.0;  // the rim finish() built the model at; tf.rim_mm is the lid
  surface::FloorPlane floor;
  const pv_status_t st = transform_query(s, &tf, &model_rim_mm, &floor);
  if (st != PV_OK) return st;
  levelling::Transform t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) t.R(r, c) = tf.rotation[3 * r + c];
    t.t(r) = tf.translation_mm[r];
  }
  const surface::Params p = scaled_params(surface_params(s->cfg), s->surface_scale_eighths / 8.0);
  surface::Model m;
  const surface::Status bs = build_surface_model(s, t, model_rim_mm, 1, p, floor, &m);  // as finish()
  if (bs == surface::Status::TooFewPoints) return PV_ERR_TOO_FEW_POINTS;
  if (bs != surface::Status::Ok) return PV_ERR_TOO_FEW_LAYERS;
  grid->axis_x_mm = m.axis.cx0;
  grid->axis_y_mm = m.axis.cy0;
  grid->axis_dx = m.axis.cx1;
  grid->axis_dy = m.axis.cy1;
  grid->z0_mm = m.z0_mm;
  grid->dz_mm = p.dz_mm;
  grid->rim_mm = tf.rim_mm;  // as depth_mm
  grid->theta_bins = s->surf.cap.theta_bins;
  grid->z_bins = m.z_bins;
  const size_t n = size_t(grid->theta_bins) * grid->z_bins;
  if (radius_mm == nullptr && state == nullptr) return PV_OK;
  if (capacity < n) return PV_ERR_INVALID_ARGUMENT;
  for (size_t i = 0; i < n; ++i) {
    if (radius_mm != nullptr) radius_mm[i] = s->surf.wall_val[i];
    if (state != nullptr) state[i] = public_state(s->surf.wall[i], p);
  }
  return PV_OK;
}

}  // namespace

}  // namespace pv::session

extern "C" pv_status_t pv_session_wall_grid(pv_session_t *s, pv_wall_grid_t *grid,
                                            float *radius_mm, uint8_t *state, size_t capacity) {
  if (s == nullptr || grid == nullptr) return PV_ERR_INVALID_ARGUMENT;
  std::memset(grid, 0, sizeof *grid);
#if defined(__cpp_exceptions)  // as pv_session_finish: nothing escapes the ABI
  try {
    return pv::session::query(s, grid, radius_mm, state, capacity);
  } catch (const std::bad_alloc &) {
    return PV_ERR_OUT_OF_MEMORY;
  } catch (...) {
    return PV_ERR_INTERNAL;
  }
#else
  return pv::session::query(s, grid, radius_mm, state, capacity);
#endif
}
