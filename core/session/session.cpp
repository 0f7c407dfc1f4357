// The C ABI of the core: session lifecycle and the ingest path.
//
// push() is the hot path: per point a validity check, a duplicate check, a
// hash, a sample offer, a levelled height and a bin insert. It never
// allocates; the plane refinement it triggers now and then works in
// preallocated scratch.
#include <cmath>
#include <cstring>
#include <new>

#include "common/point_hash.h"
#include "session/session_impl.h"

namespace pv::session {

namespace {

bool valid_point(const pv_point_t &p) {
  return std::isfinite(p.x_mm) && std::isfinite(p.y_mm) && std::isfinite(p.z_mm) &&
         std::fabs(p.x_mm) < kAbsurdMm && std::fabs(p.y_mm) < kAbsurdMm &&
         std::fabs(p.z_mm) < kAbsurdMm;
}

void set_provisional(pv_session *s, const levelling::Transform &t) {
  s->provisional = t;
  const double row[3] = {t.R(2, 0), t.R(2, 1), t.R(2, 2)};
  s->provisional_map = gridding::layer_map(s->grid, row, t.t.z());
  if (s->past_maps != nullptr && s->past_map_count < pv_session::kPastMaps) {
    s->past_maps[s->past_map_count++] = s->provisional_map;
  }
}

// How far a refined provisional frame may move the heights of the points
// binned so far and still count their places against the grid (refine()).
constexpr double kFrameMovedMm = 10.0;

// Repeat mode: the point's copy came before it, under one of the frames
// binned with since (which one, the stream does not say). It was stored in
// that frame's bin and is held there, or that bin's level turned it away
// (levels only rise), or it fell outside the grid: each ends it. A new
// point is taken for a copy only where an earlier frame's bin has thinned
// harder than its own (frames differ by fractions of a layer once the
// first refinements are past) or put it outside the grid.
bool binned_before(const pv_session *s, const P3 &p, uint64_t hash) {
  for (uint32_t k = 0; k < s->past_map_count; ++k) {
    const int64_t j = s->past_maps[k].layer_of(p);
    if (j < 0) return true;
    const bool floor = uint32_t(j) < s->floor_layers;
    const binning::LayerBins &b = floor ? s->floor_bins : s->bins;
    const uint32_t bin = floor ? 0 : uint32_t(j);
    if (!binning::LayerBins::passes(hash, b.level(bin)) || b.holds(bin, p)) return true;
  }
  return false;
}

void bin_point(pv_session *s, const P3 &p, uint64_t hash) {
  if (s->repeat_mode && binned_before(s, p, hash)) return;
  const int64_t j = s->provisional_map.layer_of(p);
  if (j < 0) {
    ++s->points_out_of_range;
    if (s->provisional_map.above(p)) ++s->points_above_range;
    return;
  }
  if (uint32_t(j) < s->floor_layers) {
    s->floor_bins.insert(0, p, hash);
    return;
  }
  s->bins.insert(uint32_t(j), p, hash);
}

// The stream repeats itself beyond the duplicate filter's window (a point
// the levelling sample holds came again: a scan sent twice over, not
// interleaved): from now on every point is looked up in the bins it could
// have gone to before it is stored (binned_before()). Sent whole five times
// over, a bowl kept a fifth of its distinct points per bin and read -0.4 %
// from its single copy; containers up to 0.5 % and NO_RIM (docs/reliability.md).
void start_repeat_mode(pv_session *s) {
  if (!s->bins.start_index()) return;  // no index (no duplicate filter): no repeat mode
  if (s->floor_layers > 0) s->floor_bins.start_index();
  s->repeat_mode = true;
}

// Re-estimates the provisional plane from the sample. Later points are
// binned with it; points already binned are re-assigned at finish.
void refine(pv_session *s) {
  // The first fit searches both orientations; later ones refine the last,
  // unless the search from both, as finish() does it, turns the scan over:
  // a scan that starts over the ground can be levelled upside down by its
  // first points, and refining kept it so; the ground then went to the
  // floor store, where neither the rim plane nor the ground looks (a
  // 754 mm pit read its rim at 722 mm).
  levelling::Transform t;
  levelling::Status st = levelling::Status::NoPlane;
  if (s->have_fit) {
    st = fit_sample(s, &t, &s->provisional.R);
    levelling::Transform both;
    if (fit_sample(s, &both, nullptr) == levelling::Status::Ok &&
        (st != levelling::Status::Ok || both.R.row(2).dot(t.R.row(2)) < 0.0)) {
      t = both;
      st = levelling::Status::Ok;
    }
  } else {
    st = fit_sample(s, &t, nullptr);
  }
  if (st == levelling::Status::Ok) {
    // Points above the grid are evidence of a pit deeper than the grid only
    // in a frame that stays: where the new frame moves the heights of the
    // points binned so far by more than kFrameMovedMm, the old frame was
    // not the pit's (the identity after a failed first fit, a fit on a
    // wall from the first thousand points) and its count starts again.
    // The MCU profile's 256-point warm-up left bulge-g-1 0.25 % of its
    // points above a 400 mm grid in the identity frame, shallow_wide-n-3
    // 2.4 % in frames 81-85 deg off, and both were refused for a depth
    // they do not have.
    double moved = 0.0;
    const uint32_t n = s->sample.size();
    for (uint32_t i = 0; i < n; ++i) {
      const double d = std::fabs(t.level_z(s->sample_points[i]) -
                                 s->provisional.level_z(s->sample_points[i]));
      if (d > moved) moved = d;
    }
    if (moved > kFrameMovedMm) {
      s->points_above_range = 0;
      // The warm-up's points are binned after this, with the new frame.
      s->points_before_frame = s->points_accepted - s->warmup_count;
    }
    set_provisional(s, t);
    s->have_fit = true;
  }
  // On failure keep the previous transform (identity at first): binning
  // still works, only the bins' thinning is less even until the next try.
  s->have_transform = true;
  s->next_refine_at = s->points_accepted * 4;
}

}  // namespace

void load_sample(pv_session *s) {
  s->sample.canonical(s->sample_sorted);
  const uint32_t n = s->sample.size();
  for (uint32_t i = 0; i < n; ++i) s->sample_points[i] = s->sample_sorted[i].p;
}

levelling::Status fit_sample(pv_session *s, levelling::Transform *t,
                             const Eigen::Matrix3d *start) {
  load_sample(s);
  const uint32_t n = s->sample.size();
  levelling::Params p;
  p.bottom_band_ratio = s->cfg.bottom_band_ratio;
  p.plane_tol_ratio = s->cfg.plane_tol_ratio;
  p.ransac_iterations = s->cfg.ransac_iterations;
  levelling::Report rep;
  return levelling::estimate(s->sample_points, n, p, s->lv, t, &rep, start);
}

void establish_transform(pv_session *s) {
  if (s->have_transform) return;
  refine(s);
  for (uint32_t i = 0; i < s->warmup_count; ++i) {
    bin_point(s, s->warmup[i], point_hash(s->warmup[i]));
  }
  s->warmup_count = 0;
}

// Stored points from which the surface model keeps each point's theta bin
// between its passes even where that grows the block.
constexpr size_t kThetaCacheMinPoints = 100000;
// The bins' thinning floor (binning/layer_bins.h): no bin keeps points at a
// higher rate than the 64th densest (32 mm of wall at 0.5 mm layers, under
// half the shallowest pit's). Single scans of the standard set never lift
// it (every bin but a few at level 0 or 1); a scan ten times as long lifts
// it to level 3, and the strays' share of the store stays the stream's.
// Only with the ranks (100,000 slots or more): the MCU profile's 64-point
// bins are all thinned hard already, and a floor over 64 of a pit's 135
// layers of 2 mm thinned those near the rim further (its volume moved
// 0.12 % from the default's; 16 layers moved it 0.4 %).
constexpr uint32_t kThinFloorLayers = 64;
// Stored points (slots) from which the bins keep their points' ranks.
constexpr size_t kRanksMinPoints = 100000;

size_t layout(const pv_config_t &c, unsigned char *block, pv_session *s) {
  Carver cv(block);
  const uint32_t layers = grid_layers(c);
  const uint32_t work = layer_work_capacity(c);
  const uint32_t k = c.level_sample_points;
  pv_session tmp{};
  pv_session *o = s ? s : &tmp;

  // What lives across calls: the sample, the bins, the per-layer results.
  // With the duplicate filter (resent points must not move the volume),
  // the sample also keeps its points distinct: a whole scan sent again
  // comes too late for the filter's window (levelling/hash_sample.h).
  levelling::SampleEntry *sample_mem = cv.take<levelling::SampleEntry>(k);
  uint64_t *sample_set = c.duplicate_filter != 0
                             ? cv.take<uint64_t>(levelling::HashSample::set_slots_for(k))
                             : nullptr;
  o->sample.init(sample_mem, k, block != nullptr ? sample_set : nullptr);
  // And the frames the bins were filled with, for a scan sent again whole
  // (start_repeat_mode()).
  gridding::LayerMap *maps =
      c.duplicate_filter != 0 ? cv.take<gridding::LayerMap>(pv_session::kPastMaps) : nullptr;
  o->past_maps = block != nullptr ? maps : nullptr;
  if (c.duplicate_filter != 0) {
    void *dup_mem = cv.take<uint64_t>(binning::DuplicateFilter::bytes_needed() / sizeof(uint64_t));
    if (block != nullptr) o->duplicates.init(dup_mem);
  }
  // The bins keep their points' ranks (one byte a slot: a full bin thins
  // without hashing its points again) in a configuration that
  // stores many points (the default: 1.4 MB, 4.5 % of its block); a small
  // one (the MCU profile, whose every byte counts) hashes again.
  const size_t slots = size_t(layers) * c.points_per_layer +
                       (c.method == PV_METHOD_SURFACE ? c.surface_floor_points : 0);
  const bool ranks = slots >= kRanksMinPoints;
  // The index of what the bins hold, for a scan sent again (repeat mode,
  // bin_point()): with the duplicate filter, as its wider reach.
  const bool index = c.duplicate_filter != 0;
  void *bins_mem = cv.take<unsigned char>(
      binning::LayerBins::bytes_needed(layers, c.points_per_layer, ranks, index));
  if (block != nullptr) o->bins.init(bins_mem, layers, c.points_per_layer, ranks,
                                      ranks ? kThinFloorLayers : 0, index);
  o->layer_start = cv.take<uint32_t>(layers + 1);
  o->layer_weight = cv.take<double>(layers);
  o->seq_z = cv.take<double>(layers);
  o->seq_area = cv.take<double>(layers);
  o->seq_keep = cv.take<uint8_t>(layers);
  o->seq_scratch_cap = sequence_scratch_doubles(layers);
  o->seq_scratch = cv.take<double>(o->seq_scratch_cap);
  o->layer_info = cv.take<pv_layer_info_t>(layers);
  if (c.method == PV_METHOD_SURFACE) {
    void *floor_mem = cv.take<unsigned char>(
        binning::LayerBins::bytes_needed(1, c.surface_floor_points, ranks, index));
    if (block != nullptr) o->floor_bins.init(floor_mem, 1, c.surface_floor_points, ranks, 0, index);
  }

  // Scratch: the levelling's, the warm-up buffer (empty once a transform
  // exists, which measure() makes sure of first) and the per-layer stages'.
  const size_t scratch_at = cv.used();
  o->sample_sorted = cv.take<levelling::SampleEntry>(k);
  o->sample_points = cv.take<P3>(k);
  o->lv.a = cv.take<Eigen::Vector3d>(k);
  o->lv.b = cv.take<Eigen::Vector3d>(k);
  o->lv.c = cv.take<Eigen::Vector3d>(k);
  o->lv.v = cv.take<double>(k);
  o->warmup = cv.take<P3>(c.warmup_points);
  o->order = c.method == PV_METHOD_SURFACE
                 ? nullptr
                 : cv.take<uint32_t>(size_t(layers) * c.points_per_layer);
  o->layer_pts = cv.take<XY>(work);
  const size_t thin_bytes = thinning::workspace_bytes(work);
  void *thin_mem = cv.take<unsigned char>(thin_bytes);
  if (block != nullptr) thinning::make_workspace(thin_mem, thin_bytes, work, &o->thin_ws);
  o->cluster_scratch_cap = work;
  o->cluster_scratch = cv.take<double>(work);
  o->area_scratch_cap = area_scratch_points(work);
  o->area_scratch = cv.take<XY>(o->area_scratch_cap);
  o->polar_scratch_cap = area::polar_scratch_needed(work);
  o->polar_scratch = cv.take<double>(o->polar_scratch_cap);
  o->theta_cache = nullptr;
  o->theta_cache_cap = 0;
  // The surface model overlays that scratch. Method surface builds it in
  // measure_surface(), after the levelling, the rim and the layer counts are
  // done with the scratch; paper and polar build it for their plausibility
  // checks (check_pit_shape()), after their per-layer stages. It is not read
  // after either returns.
  const size_t scratch_end = cv.used();
  cv.rewind(scratch_at);
  const surface::Capacity sc = surface_capacity(c);
  void *surf_mem = cv.take<unsigned char>(surface::bytes_needed(sc));
  if (block != nullptr) surface::make_workspace(surf_mem, sc, &o->surf);
  if (c.method == PV_METHOD_SURFACE) {
    // One byte per stored point: its theta bin, computed by the first pass
    // over the points and read by the others (the angle is a pass's costliest
    // part). A speed-up for configurations that store many points (the
    // default: 1.4 MB, 4.5 % of its block); a small one (the MCU profile,
    // whose every byte counts) bins each point again in each pass, unless
    // the scratch has room.
    const size_t cache = size_t(layers) * c.points_per_layer + c.surface_floor_points;
    if (cv.used() + cache + 64 <= scratch_end || cache >= kThetaCacheMinPoints) {
      o->theta_cache_cap = uint32_t(cache);  // < 2^27: the slots are validated
      o->theta_cache = cv.take<uint8_t>(cache);
    }
  }
  if (cv.used() < scratch_end) cv.rewind(scratch_end);
  return cv.used();
}

}  // namespace pv::session

using namespace pv;

namespace {

void reset_counters(pv_session *s) {
  s->finished = false;
  s->points_in = s->points_invalid = s->points_out_of_range = s->points_above_range = 0;
  s->points_before_frame = 0;
  s->points_duplicate = s->points_accepted = 0;
  if (s->cfg.duplicate_filter != 0) s->duplicates.clear();
  s->sample.clear();
  session::set_provisional(s, levelling::Transform{});
  s->past_map_count = 0;
  s->repeat_mode = false;
  s->surface_start = 0;
  s->surface_scale_eighths = 8;
  s->surface_no_ground = 0;
  s->have_transform = false;
  s->have_fit = false;
  s->next_refine_at = 0;
  s->warmup_count = 0;
  s->bins.clear();
  if (s->floor_layers > 0) s->floor_bins.clear();
  s->layer_info_count = 0;
}

}  // namespace

extern "C" pv_status_t pv_session_size(const pv_config_t *cfg, size_t *bytes_out) {
  if (cfg == nullptr || bytes_out == nullptr) return PV_ERR_INVALID_ARGUMENT;
  if (pv_config_validate(cfg, nullptr) != PV_OK) return PV_ERR_INVALID_CONFIG;
  *bytes_out = PV_BLOCK_ALIGN * ((sizeof(pv_session) + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN) +
               session::layout(*cfg, nullptr, nullptr);
  return PV_OK;
}

extern "C" pv_status_t pv_session_init(const pv_config_t *cfg, void *block, size_t bytes,
                                       pv_session_t **session_out) {
  if (cfg == nullptr || block == nullptr || session_out == nullptr) return PV_ERR_INVALID_ARGUMENT;
  size_t need = 0;
  const pv_status_t st = pv_session_size(cfg, &need);
  if (st != PV_OK) return st;
  if (bytes < need) return PV_ERR_BLOCK_TOO_SMALL;
  if (reinterpret_cast<uintptr_t>(block) % PV_BLOCK_ALIGN != 0) return PV_ERR_BLOCK_MISALIGNED;
  auto *base = static_cast<unsigned char *>(block);
  auto *s = new (base) pv_session{};  // placement: no allocation
  s->cfg = *cfg;
  s->grid.layer_mm = cfg->layer_mm;
  s->grid.layers = session::grid_layers(*cfg);
  s->grid.below = gridding::layers_below(
      cfg->layer_mm,
      cfg->method == PV_METHOD_SURFACE ? gridding::kSurfaceBelowMm : gridding::kBelowMm);
  s->floor_layers = cfg->method == PV_METHOD_SURFACE
                        ? s->grid.below + uint32_t(session::kFloorStoreTopMm / cfg->layer_mm)
                        : 0;
  const size_t head = PV_BLOCK_ALIGN * ((sizeof(pv_session) + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN);
  session::layout(*cfg, base + head, s);
  reset_counters(s);
  *session_out = s;
  return PV_OK;
}

extern "C" pv_status_t pv_session_push(pv_session_t *s, const pv_point_t *points, size_t count) {
  if (s == nullptr || (points == nullptr && count > 0)) return PV_ERR_INVALID_ARGUMENT;
  if (s->finished) return PV_ERR_WRONG_STATE;
  // Per batch of kBatch points: validity and the duplicate filter first (the
  // filter's table lookups overlap), as bit masks, then the accepted points
  // in order. The per-point work after that is the hash, the sample's
  // one-compare rejection, the provisional layer and the bin store, all
  // inline.
  constexpr size_t kBatch = binning::DuplicateFilter::kBatch;
  static_assert(kBatch == 64, "a batch's masks are 64-bit words");
  const bool filter = s->cfg.duplicate_filter != 0;
  for (size_t base = 0; base < count; base += kBatch) {
    const size_t m = count - base < kBatch ? count - base : kBatch;
    const pv_point_t *batch = points + base;
    uint64_t valid = 0, duplicate = 0;
    if (filter) {
      duplicate = s->duplicates.filter_batch(batch, m, &valid);
    } else {
      for (size_t k = 0; k < m; ++k) valid |= uint64_t(session::valid_point(batch[k]) ? 1 : 0) << k;
    }
    const uint64_t all = m == kBatch ? ~uint64_t(0) : (uint64_t(1) << m) - 1;
    const uint64_t accept = valid & ~duplicate;
    s->points_in += m;
    s->points_invalid += uint64_t(__builtin_popcountll(all & ~valid));
    s->points_duplicate += uint64_t(__builtin_popcountll(valid & duplicate));
    for (uint64_t left = accept; left != 0; left &= left - 1) {
      const pv_point_t &q = batch[__builtin_ctzll(left)];
      ++s->points_accepted;
      const P3 p{q.x_mm, q.y_mm, q.z_mm};
      const uint64_t h = point_hash(p);
      s->sample.offer(p, h);
      // Per point, not per batch: where the repeat is seen does not depend
      // on how the caller cut the stream into pushes.
      if (!s->repeat_mode && s->have_transform &&
          (s->sample.repeated() || s->bins.copy_refused() || s->floor_bins.copy_refused())) {
        session::start_repeat_mode(s);
      }
      if (!s->have_transform) {
        s->warmup[s->warmup_count++] = p;
        if (s->warmup_count == s->cfg.warmup_points) session::establish_transform(s);
        continue;
      }
      session::bin_point(s, p, h);
      if (s->points_accepted >= s->next_refine_at) session::refine(s);
    }
  }
  return PV_OK;
}

namespace {

// measure() reports every failure as a status and neither throws nor
// allocates (the last allocation, the kd-tree of adaptive thinning, is gone).
// Host builds with exceptions still turn a stray one into a status rather
// than let it cross the C ABI; the MCU builds without exceptions.
pv_status_t guarded_measure(pv_session *s, pv_result_t *out) {
#if defined(__cpp_exceptions)
  try {
    return session::measure(s, out);
  } catch (const std::bad_alloc &) {
    out->status = PV_ERR_OUT_OF_MEMORY;
    return PV_ERR_OUT_OF_MEMORY;
  } catch (...) {
    out->status = PV_ERR_INTERNAL;
    return PV_ERR_INTERNAL;
  }
#else
  return session::measure(s, out);
#endif
}

}  // namespace

extern "C" pv_status_t pv_session_estimate(pv_session_t *s, pv_result_t *out) {
  if (s == nullptr || out == nullptr) return PV_ERR_INVALID_ARGUMENT;
  if (s->finished) return PV_ERR_WRONG_STATE;
  if (!s->have_transform) {
    // Still warming up: fixing the plane now, from a few points, would bin
    // the rest of the scan with it and lose points outside its range (an
    // estimate right after init changed the final volume). No estimate yet.
    std::memset(out, 0, sizeof *out);
    out->points_in = s->points_in;
    out->points_invalid = s->points_invalid;
    out->status = PV_ERR_TOO_FEW_POINTS;
    return out->status;
  }
  s->estimating = true;
  const pv_status_t st = guarded_measure(s, out);
  s->estimating = false;
  return st;
}

extern "C" pv_status_t pv_session_finish(pv_session_t *s, pv_result_t *out) {
  if (s == nullptr || out == nullptr) return PV_ERR_INVALID_ARGUMENT;
  if (s->finished) return PV_ERR_WRONG_STATE;
  const pv_status_t st = guarded_measure(s, out);
  s->finished = true;
  return st;
}

extern "C" pv_status_t pv_session_reset(pv_session_t *s) {
  if (s == nullptr) return PV_ERR_INVALID_ARGUMENT;
  reset_counters(s);
  return PV_OK;
}

extern "C" pv_status_t pv_session_layers(const pv_session_t *s, pv_layer_info_t *out,
                                         size_t capacity, size_t *count_out) {
  if (s == nullptr || count_out == nullptr || (out == nullptr && capacity > 0)) {
    return PV_ERR_INVALID_ARGUMENT;
  }
  const size_t n = s->layer_info_count < capacity ? s->layer_info_count : capacity;
  if (n > 0) std::memcpy(out, s->layer_info, n * sizeof *out);
  *count_out = n;
  return PV_OK;
}
