// The session object and its memory layout. Private to core/session.
#ifndef PV_SESSION_SESSION_IMPL_H
#define PV_SESSION_SESSION_IMPL_H

#include <cstddef>
#include <cstdint>

#include "binning/duplicate_filter.h"
#include "binning/layer_bins.h"
#include "common/geometry.h"
#include "gridding/gridding.h"
#include "levelling/hash_sample.h"
#include "levelling/levelling.h"
#include "pitvol/pitvol.h"
#include "area/area_fit.h"
#include "area/polar_area.h"
#include "cleanup/mad_filter.h"
#include "surface/surface_model.h"
#include "thinning/adaptive_thinning.h"
#include "volume/volume.h"

namespace pv::session {

// Carves aligned regions out of the block in a fixed order. With a null
// base it only counts, which is how pv_session_size() is computed: the size
// and the layout cannot disagree.
class Carver {
 public:
  explicit Carver(unsigned char *base) : base_(base) {}
  template <class T>
  T *take(size_t count) {
    offset_ = (offset_ + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN;
    T *p = base_ ? reinterpret_cast<T *>(base_ + offset_) : nullptr;
    offset_ += count * sizeof(T);
    return p;
  }
  size_t used() const { return offset_; }
  // Back to an earlier offset: the regions after it are overlaid by what is
  // taken next (phases that never run at the same time).
  void rewind(size_t offset) { offset_ = offset; }

 private:
  unsigned char *base_;
  size_t offset_ = 0;
};

// Points one final layer may hold when it is processed (twice a bin: a
// final layer can draw on two provisional bins when the plane moved).
inline uint32_t layer_work_capacity(const pv_config_t &c) { return 2 * c.points_per_layer; }

// Layers of the grid: max_layers of depth range (the paper's grid keeps
// its few millimetres below the bottom plane inside them); method surface
// keeps 40 mm below the plane (bowls, uneven floors) on top of them, so its
// depth range is not shorter.
inline uint32_t grid_layers(const pv_config_t &c) {
  if (c.method != PV_METHOD_SURFACE) return c.max_layers;
  return c.max_layers + gridding::layers_below(c.layer_mm, gridding::kSurfaceBelowMm) -
         gridding::layers_below(c.layer_mm);
}

// Method surface: the floor is the densest surface of a scan and lies in
// two or three 0.5 mm layers, whose bins thin it to a few points per
// square centimetre while the multipath above it is kept whole (measured:
// 2 mm floor cells with three points were rare, and multipath made false
// floor). Its points (provisional height below kFloorStoreTopMm) go to one
// larger store instead of their layer bins: pv_config_t.surface_floor_points
// (65,536 by default; a full store thins itself like a layer bin).
constexpr double kFloorStoreTopMm = 20.0;
// The smallest test hole: ASTM D1556 asks at least 710 cm3 (maximum particle
// 4.75 mm), BS 1377's small pouring cylinder digs about 1.2 L. Files carry
// no units: a pit scanned in centimetres and read as millimetres comes out
// 1000 times small (a 0.5 m3 pit as 0.5 L), in metres 10^9 times. Below
// 600 cm3 the scan is refused with its units named, never measured
// (PV_PIT_CHECK_TOO_SMALL: measure.cpp before the model, from a bound;
// measure_surface.cpp after it, from the volume).
constexpr double kMinVolumeCm3 = 600.0;

// The surface model's grids (method surface, and paper's and polar's
// plausibility checks): the whole depth range, and pits up to
// pv_config_t.surface_max_radius_mm around their axis; bin sizes from the
// configuration too (the MCU profile's are coarser).
inline surface::Params surface_params(const pv_config_t &c) {
  surface::Params p;
  p.theta_bins = c.surface_theta_bins;
  p.dz_mm = double(c.surface_wall_dz_mm);
  p.cell_mm = double(c.surface_cell_mm);
  p.band_mm = double(c.surface_band_mm);
  p.coarse_bins = c.surface_coarse_bins != 0;
  // Rings of the volume integration: half a floor cell (1 mm by default),
  // finer would only resample the same cells; sizes the ray arrays.
  p.integrate_dr_mm = 0.5 * p.cell_mm;
  return p;
}
inline surface::Capacity surface_capacity(const pv_config_t &c) {
  return surface::capacity_for(surface_params(c), double(grid_layers(c)) * c.layer_mm,
                               double(c.surface_max_radius_mm));
}

inline size_t area_scratch_points(size_t work) { return area::scratch_needed(work); }

// The area sequence scratch serves both the MAD filter and the integration.
inline size_t sequence_scratch_doubles(size_t layers) {
  const size_t a = cleanup::scratch_needed(layers);
  const size_t b = volume::scratch_needed_between(layers);
  return a > b ? a : b;
}

}  // namespace pv::session

struct pv_session {
  pv_config_t cfg;
  bool finished;
  bool estimating;  // measure() runs for pv_session_estimate (a live figure)
  // Levelling: a provisional transform exists; it came from a successful fit.
  // (The flags sit together: padding between fields is block bytes.)
  bool have_transform;
  bool have_fit;
  bool repeat_mode;  // session.cpp, start_repeat_mode()
  uint8_t past_map_count;  // of past_maps below
  // The start method surface's last measure() levelled from (a
  // SurfaceStart: later than the floor plane's where the frame from that
  // was refused, measure.cpp, kRetriedChecks). The transform query levels
  // the same way.
  uint8_t surface_start;
  // The scale of the grids method surface's last model was built on, in
  // eighths (measure_surface.cpp, grid_scale_for(): 8 on the configured
  // grids, up to 22 for the widest pits). The wall-grid query builds on it.
  uint8_t surface_scale_eighths;
  // Nonzero: the last measure() levelled without grounds (level_surface.cpp,
  // level_on_opening; measure.cpp, a "ground" under the pit's top). The
  // transform query levels the same way.
  uint8_t surface_no_ground;
  // The last frame method surface measured was refused for its weak
  // opening's lean (measure_surface.cpp, kMaxWeakFrameLean): the frame is
  // wrong, and measure.cpp tries the later starts.
  bool weak_frame_leaned;

  uint64_t points_in;
  uint64_t points_invalid;
  uint64_t points_out_of_range;
  // Of those, above the grid's top when binned with the provisional frame
  // that stands, and the points binned before that frame (refine()).
  uint64_t points_above_range;
  uint64_t points_before_frame;
  // Resent points (binning/duplicate_filter.h) are counted in points_in and
  // here, and go no further; the refinement schedule counts the rest.
  uint64_t points_duplicate;
  uint64_t points_accepted;  // valid and not a duplicate
  pv::binning::DuplicateFilter duplicates;

  // Levelling: order-independent sample, provisional transform.
  pv::levelling::HashSample sample;
  pv::levelling::SampleEntry *sample_sorted;
  pv::P3 *sample_points;
  pv::levelling::Scratch lv;
  pv::levelling::Transform provisional;
  pv::gridding::LayerMap provisional_map;  // provisional, folded for push()
  // Every frame points were binned with, in order (repeat mode looks a
  // point up under each), carved with the duplicate filter (else null):
  // refinements come at 4x the points each, so 16 frames last past 10^13
  // points; later ones are not recorded.
  static constexpr uint32_t kPastMaps = 16;
  pv::gridding::LayerMap *past_maps;
  uint64_t next_refine_at;

  // Points that arrived before the first plane.
  pv::P3 *warmup;
  uint32_t warmup_count;
  uint32_t floor_layers;  // method surface: provisional layers below this go
                          // to floor_bins (0: none); beside warmup_count, no padding

  pv::gridding::Grid grid;
  pv::binning::LayerBins bins;
  pv::binning::LayerBins floor_bins;  // method surface: one bin for the floor band

  // Finish-time scratch (bounded, inside the block).
  uint32_t *order;        // slot ids sorted by final layer
  uint32_t *layer_start;  // layers + 1
  double *layer_weight;   // layers
  pv::XY *layer_pts;      // layer_work_capacity
  pv::thinning::Workspace thin_ws;
  double *cluster_scratch;
  size_t cluster_scratch_cap;
  pv::XY *area_scratch;
  size_t area_scratch_cap;
  double *polar_scratch;  // method polar only
  size_t polar_scratch_cap;
  double *seq_z;          // layers
  double *seq_area;       // layers
  uint8_t *seq_keep;      // layers
  double *seq_scratch;
  size_t seq_scratch_cap;
  pv_layer_info_t *layer_info;  // layers
  uint32_t layer_info_count;
  uint32_t theta_cache_cap;  // entries (stored points: bins and floor store)
  pv::surface::Workspace surf;  // method surface only (else empty)
  uint8_t *theta_cache;   // method surface: each stored point's theta bin between passes
};

namespace pv::session {

// Lays the session out in block (or counts bytes when block is null).
size_t layout(const pv_config_t &cfg, unsigned char *block, pv_session *s);
// The canonical sample into s->sample_points (scratch: the surface model
// overlays it), as fit_sample() reads it.
void load_sample(pv_session *s);
// Fits the levelling transform on the canonical (sorted) sample. The
// provisional refinements and the final fit share it, so they cannot differ
// in anything but the points seen so far.
// start: see levelling::estimate (NULL: the full, order-independent fit).
levelling::Status fit_sample(pv_session *s, levelling::Transform *t,
                             const Eigen::Matrix3d *start = nullptr);
// Makes sure a transform exists and the warm-up points are binned.
void establish_transform(pv_session *s);
// estimate() and finish() share this; it reads the bins, writes scratch.
pv_status_t measure(pv_session *s, pv_result_t *out);
// Where level_for_surface() starts: the floor plane's frame, the
// scanner's axis, the scanner's axis turned 30 and 50 deg.
enum class SurfaceStart : uint8_t { floor_plane, axis, turned_axis };
struct Opening {
  // A plane of the opening was found (else t is the floor plane's frame,
  // which on a pit without a flat floor can be 10-40 deg off).
  bool found = false;
  // The rim height when a plane other than the ground set it, else
  // negative (the rim stage decides).
  double rim_mm = -1.0;
  // rim_mm was set by the rim plane (not the support plane): the lid is
  // read from the points about it (lid_shift_mm()).
  bool rim_plane = false;
  // rim_mm was set by a rim plane through part of the sectors (the last
  // resort of level_on_opening()).
  bool partial = false;
  // Levelled on the ground: its plane's height, the rim where the ground's
  // peak is not found (sparse ground under strays); else negative.
  double ground_mm = -1.0;
  // The start whose frame it is; turned_axis also where every start was
  // tried and the floor plane's sideways frame stayed.
  SurfaceStart start = SurfaceStart::floor_plane;
  // The levelling's floor plane in this frame (floor_plane_in()).
  surface::FloorPlane floor;
};
// Levelled on the ground (level_on_ground, also after a turn), not on a
// rim or support plane, which set the rim height.
inline bool on_ground(const Opening &o) { return !(o.rim_mm > 0); }
// Two frames whose ups lie within 3 deg of each other are one frame
// (level_surface.cpp, the turned starts' votes; measure.cpp, the retries).
constexpr double kAgreeCos = 0.99862953475457387;  // cos 3 deg
// Levelled on a plane that may touch the opening on one side only: the
// support plane, or a rim plane through part of the sectors. A frame from
// either is held to the pit's own axis (measure_surface.cpp,
// kMaxWeakFrameLean).
inline bool weak_opening(const Opening &o) { return !on_ground(o) && (!o.rim_plane || o.partial); }
// Method surface: re-levels t on the plane of the opening: the ground ring
// when the scan has one, else the rim plane (the wall's top edge), else the
// support plane, from the floor-plane frame, then from the scanner-upright
// one, then from that turned (level_surface.cpp). from: the first start
// tried (the later ones follow where it finds no opening facing the
// scanner).
Opening level_for_surface(pv_session *s, levelling::Transform *t,
                          SurfaceStart from = SurfaceStart::floor_plane);
// Method surface measures below the opening: true where none was found
// from either start (level_surface.cpp says where that is not refused).
bool opening_missing(const pv_session *s, const Opening &o);
// The rim in frame t short of the wall's top: the opening's plane (rim or
// support plane), else the ground ring's peak in the sample's heights,
// else the ground's plane. Every method (an empty Opening: the peak only).
struct Rim {
  bool found = false;
  double mm = -1.0;
  bool from_ground = false;
};
Rim opening_rim(pv_session *s, const levelling::Transform &t, const Opening &o);
// The lid's height in frame t against the rim the model sorts the points
// about: where a rim plane set the rim (o.rim_plane, o.rim_mm), from the
// stored points about it (rim/rim_profile.h: the plane's sector tops are
// order statistics that rise with the scan's length), else 0. One pass
// over the store, made only for the frame measured.
double lid_shift_mm(const pv_session *s, const levelling::Transform &t, const Opening &o);
// pv_session_transform()'s query (transform_query.cpp): out->rim_mm is
// the lid (as pv_result_t.depth_mm), model_rim_mm the rim finish() built
// its surface model at (the wall-grid query builds the same model), floor
// (if not null) the levelling's floor plane in that frame.
pv_status_t transform_query(pv_session *s, pv_transform_t *out, double *model_rim_mm,
                            surface::FloorPlane *floor = nullptr);
// The surface method's part of measure(): from the levelled stored points,
// the rim and the bottom of the grid to the result (measure_surface.cpp).
// lid_shift: the lid's height against rim_mm (lid_shift_mm()); floor: the
// levelling's floor plane in frame t (Opening::floor); weak: the frame is
// levelled on a weak opening (weak_opening()).
pv_status_t measure_surface(pv_session *s, const levelling::Transform &t, double rim_mm,
                            double lid_shift, const surface::FloorPlane &floor, bool weak,
                            pv_result_t *out);
// The surface model of the stored points levelled by t, in s->surf: the
// build step of measure_surface(), shared with the wall-grid query so that
// both see the same points in the same order (every stride-th of a bin).
surface::Status build_surface_model(pv_session *s, const levelling::Transform &t, double rim_mm,
                                    uint32_t stride, const surface::Params &p,
                                    const surface::FloorPlane &floor, surface::Model *m);
// The surface parameters on grids scaled by `scale` (pits wider than
// surface_max_radius_mm): the floor cells and the integration rings.
surface::Params scaled_params(surface::Params p, double scale);
// Paper and polar: method surface's plausibility checks on the same points
// (measure_surface.cpp); overwrites the area sequence. PV_OK, or the status
// to refuse with.
pv_status_t check_pit_shape(pv_session *s, const levelling::Transform &t, double rim_mm,
                            pv_result_t *out);

}  // namespace pv::session

#endif
