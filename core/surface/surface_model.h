// The surface model of a pit (method `surface`, docs/method.md).
//
// The paper fits each 0.5 mm layer on its own; a handheld scan sees the
// lower wall at grazing angles, so sparse layers, floor multipath and
// unseen bands decide its error. Here the whole pit is one surface:
// - the wall as a radius grid R(theta, z) around a leaning axis (a line
//   through the centres of coarse slabs), on theta_bins x dz bins;
// - the floor as a height map on a Cartesian grid of cell_mm cells.
// A wall bin's value comes from the points on its surface: those within
// band_mm of the bin's second-largest radius (the largest may be a stray;
// multipath lies inside the surface, at smaller radii, and never reaches
// the band), fitted by r = a + b (z - z_centre) so that a sloping wall is
// read at the bin's centre height, not at its top. The floor map does the
// same from below: the points within band_mm of a cell's second-lowest z.
// Bins the scan did not see are bridged from their neighbours (linear
// along z where seen bins bracket them, then from around), and bridged
// again with the lower and the higher neighbour: those two volumes give
// the unseen band's share of the interval.
//
// Volume: the void is {r < R(theta, z)} intersected with {z > floor(x, y)}
// below the rim plane, integrated on a polar grid around the axis. Each
// constraint over-estimates the void where it carries no information (the
// wall near a flat floor, the floor map beyond the wall) and the
// intersection is the pit.
//
// Memory: everything lives in caller memory sized by bytes_needed(); the
// model is built at finish from the stored points, in five passes over
// them (centroid, axis slabs, two grid passes, floor share), with no
// allocation. Speed (docs/method.md): theta bins without atan2
// (angle_bins.h), each point's bin kept from the first grid pass for the
// later ones (Workspace::point_theta), points in batches.
#ifndef PV_SURFACE_SURFACE_MODEL_H
#define PV_SURFACE_SURFACE_MODEL_H

#include <cstddef>
#include <cstdint>

#include "surface/angle_bins.h"

namespace pv::surface {

struct Params {
  uint32_t theta_bins = 180;       // 2 deg
  double dz_mm = 2.0;              // wall bin height
  double cell_mm = 2.0;            // floor map cell
  double band_mm = 1.5;            // surface band behind the near-extreme
  uint32_t min_points = 1;         // surface points that make a bin seen
  double inward_reject_mm = 3.0;   // sparse bin this far inside its neighbours: unseen
  uint32_t sparse_points = 6;      // bins with fewer points get the inward test
  double slab_mm = 10.0;           // axis: slab height for the centres
  double integrate_dz_mm = 0.5;    // z step of the volume integration
  double integrate_dr_mm = 1.0;    // r step of the volume integration
  double rim_guard_mm = 1.5;       // wall grid stops this far below the rim
  uint32_t min_floor_points = 3;   // surface points that make a floor cell seen
  double floor_seed_mm = 1.5;      // floor flood starts within this of the lowest cells
  double floor_bump_mm = 1.0;      // a floor cell this far above its neighbours is multipath
  double floor_wall_margin_mm = 3.0;  // floor cells this close to the wall are its foot
  double floor_max_rise_mm = 1.5;  // a larger step from cell to cell is not floor
  uint32_t short_gap_bins = 4;     // a bridge this short is interpolation, not unseen wall
  double wide_gap_deg = 30.0;      // unknown wall this wide at one height: a side unseen
  double slip_mm = 40.0;           // floor only: a second floor up to this far above
  double ghost_mm = 8.0;           // window behind the surface band where a doubled
                                   // scan's second surface lies (Model::ghost_contrast)
  // Coarse wall bins with a few points each (the MCU profile, docs/targets.md):
  // a bin too sparse to fit its slope along the angle borrows it from its
  // neighbours, and the interval counts what such bins cannot resolve
  // (Model::sparse_mm3, subbin_mm3).
  bool coarse_bins = false;
};

// Capacities, fixed when the block is laid out.
struct Capacity {
  uint32_t theta_bins;
  uint32_t z_bins;        // wall bins over the whole depth range
  uint32_t cells;         // floor map cells per side
  uint32_t slabs;         // axis slabs
  uint32_t ray_steps;     // integration steps along a ray
};

// Capacities for a depth range and a largest pit radius.
Capacity capacity_for(const Params &p, double depth_range_mm, double max_radius_mm);

struct Point {            // levelled, millimetres (bottom plane at z = 0)
  double x, y, z;
};

// The source of levelled points, read once per pass: visit(ctx, fn, fn_ctx)
// calls fn(fn_ctx, pts, n) with every stored point, in batches (a pass's
// loop over a batch inlines its per-point work: one indirect call per
// batch, not per point), always in the same order.
using PointFn = void (*)(void *fn_ctx, const Point *pts, size_t n);
struct PointSource {
  void *ctx;
  void (*visit)(void *ctx, PointFn fn, void *fn_ctx);
};

// What every point reads (top1, band) shares the first cache line.
struct WallBin {
  float top1, top2;       // two largest radii
  float band;             // surface band of this bin (wider on a slope)
  uint32_t n_all;         // points in the bin
  uint32_t n;             // surface points (within band of top2)
  uint32_t n_floor;       // of those, on the floor map's floor
  uint8_t state;          // see BinState
  uint8_t gap;            // bridged: length of the bridge, bins (255: long)
  uint16_t n_ghost;       // points up to ghost_mm inside the band (saturates)
  // Params::coarse_bins (the MCU profile): the angle of top1 from the bin
  // centre, rad. Otherwise the sum over the surface points of (top1 - r)^2,
  // small numbers whatever the radius: the band's spread about the bin's
  // fit, for the doubled-scan check (the MCU's block has no room for a
  // field more: it fills its 512 KiB region).
  union {
    float atop;
    float sdd;
  };
  double sr, sz, szz, srz;  // sums over the surface points (z from the bin centre)
  double sa, saa, sra, sza;  // the same for the angle from the bin centre, rad
};

enum BinState : uint8_t {
  kEmpty = 0, kSeen = 1, kRejected = 2, kBridged = 3,
  kFloor = 4,     // floor cell connected to the lowest floor
  kFloorBin = 5,  // wall bin whose points are floor: filled, bounded by the floor map
  kSolid = 6      // floor cell on a solid the flood went round (a stone): its top bounds the void
};

struct FloorCell {
  float low1, low2;       // two lowest heights
  uint32_t n;             // surface points (within band of low2)
  float value;            // height of the floor in this cell
  double sz;
  uint8_t state;
  uint16_t n_far;         // points from ghost_mm to slip_mm above the band
  uint32_t n_ghost;       // points up to ghost_mm above the band
};

struct Workspace {
  Capacity cap;
  WallBin *wall;          // theta_bins * z_bins
  float *wall_val;        // R at the bin centre (bridged where unseen)
  float *wall_lo, *wall_hi;  // bridged with the lower / higher neighbour
  FloorCell *floor;       // cells * cells
  float *slab_top;        // max(slabs * kAxisSectors * 2, 2 * theta_bins): two largest radii
  float *ray_floor;       // theta_bins * ray_steps: floor along each ray
  float *ray_max;         // prefix maximum of ray_floor
  // The container lip's cap per theta bin (container_lip.h), for the grid
  // passes and for what reads the model after build(): in slab_top's
  // memory, free once the axis is fit (ray_max's, where it was, integrate()
  // overwrites).
  float *lip_cap;
  // After lip_cap, in slab_top's memory: the round as a vessel's
  // (lip_caps()). A function, not a field: the MCU's session header has no
  // room for a pointer more.
  float *vessel_cap() const { return slab_top + cap.theta_bins; }
  uint32_t *fill_idx;     // theta_bins * z_bins (bridging rounds)
  float *fill_val;        // max(theta_bins * z_bins * 3, cells * cells); also the
                          // ghost depths' sums in the grid's second pass
  uint32_t *queue;        // cells * cells (floor flood)
  // Optional, the caller's: one byte per point of the PointSource, where
  // build() keeps each point's theta bin for its later passes and for
  // occupancy() (which must then visit the same points in the same order).
  // Points past point_theta_cap, or no cache (null), are binned again.
  AngleBins *theta;        // theta_bins around the axis (set up by build)
  AngleBins *sectors;      // kAxisSectors around the centroid, for the axis
  unsigned char *theta_tables, *sector_tables;  // their tables (AngleBins::bytes_for)
  uint8_t *point_theta = nullptr;
  size_t point_theta_cap = 0;
};

constexpr uint32_t kAxisSectors = 36;

size_t bytes_needed(const Capacity &c);
// memory: bytes_needed(c) bytes, 64-byte aligned.
void make_workspace(void *memory, const Capacity &c, Workspace *ws);

struct Axis {
  double cx0, cy0;        // centre at z = 0
  double cx1, cy1;        // lean: centre moves by (cx1, cy1) per mm of z
  double cx(double z) const { return cx0 + cx1 * z; }
  double cy(double z) const { return cy0 + cy1 * z; }
};

// The levelling's floor plane in the model's frame, z = a x + b y + c
// (session/level_surface.cpp). The frame is levelled on the opening; where
// the ground tilts against the pit's floor (a pit dug into a slope), the
// floor lies on this plane, tilted, not at z = 0. The floor map floods
// from the cells lowest above it (floor_map.cpp).
struct FloorPlane {
  double a = 0, b = 0, c = 0;
  double at(double x, double y) const { return a * x + b * y + c; }
};

struct Model {
  Axis axis;
  // Most capped bins' flat top is a vessel's lip (container_lip.h): where
  // a bin reads the vessel's outer wall, the lip lies inside the wall's top
  // (Occupancy::over_mouth is not counted).
  bool vessel_lip;
  // ghost_contrast is the pooled blocks' (surface_model.cpp,
  // pooled_ghost_contrast): no direction had the dense bins for the bins'.
  bool ghost_pooled;
  double z0_mm;           // bottom of the wall grid
  uint32_t z_bins;        // used (to the rim)
  double rim_mm;
  double floor_x0, floor_y0;  // corner of the floor map
  uint32_t seen_bins, bridged_bins, rejected_bins;
  uint32_t short_gap_bins;  // bridges of at most Params::short_gap_bins count as seen
  // Params::coarse_bins: volume the seen coarse bins leave uncertain, mm3,
  // for the interval (surface_model.cpp, coarse_bin): the slope sparse bins
  // borrowed, and the parts of seen bins no point fell in.
  double sparse_mm3, subbin_mm3;
  // A second surface a few mm behind the first (a scan registered twice:
  // the scanner's tracking slipped). Wall: a ghost bin is a seen bin with
  // at least kDenseBinPoints points of which 30 % or more lie in the
  // ghost_mm behind its band; a thick bin, one whose band's points spread
  // more than 0.3 mm about its plane (copies closer than the band). Two
  // copies a rigid shift apart lie apart across the wall on two opposite
  // sides and not between, so ghost_contrast is the larger of two
  // contrasts, the ghost bins' and the thick bins': the largest, over the
  // directions, of their share in the two 60 deg sectors facing that
  // direction less their share in the two sectors across it (-1: no
  // direction with kMinSectorBins dense bins in both). Grooves and
  // multipath lie all round: no contrast.
  // Floor: the points of the flooded floor cells in the band
  // (floor_points) and in the ghost_mm above it (floor_ghost_points).
  double ghost_contrast;
  // Where no direction had the dense bins for it, not even pooled, on a
  // wall small enough to pool (the smallest pits, a few points a bin): the
  // share of the wall's 10 deg sectors (kGhostSectorPoints points or more)
  // that hold a tenth of their points or more behind the band (-1: not
  // counted, or fewer than half of the sectors hold enough points).
  double sparse_ghost_share;
  uint64_t floor_points, floor_ghost_points;
  // The same over the level cells only (surface_model.cpp, level_cell()):
  // a sloping bottom (a rounded bowl's) puts its own surface in the ghost
  // window of its steep cells; a second floor lies above the level ones too.
  uint64_t floor_level_points, floor_level_ghost_points;
  // Further above it, up to Params::slip_mm: a second pass that slipped
  // along the axis doubles the floor 10-40 mm up (floor_far_points).
  uint64_t floor_far_points;
  // The floor map's cells, and those with two far points or more: a
  // slipped copy's floor spreads them over the floor, a tapered or
  // overhanging wall's foot keeps them to its edge.
  uint64_t floor_cells, floor_far_cells;
  // The share of those far points (over every floor map cell) within the
  // densest 3 mm of height: near 1 for a second floor, low for a wall
  // overhanging the floor's edge.
  double floor_far_peak;
};

// Points that make a wall bin dense enough for its ghost share, and dense
// bins that make a pair of sectors evidence for the contrast.
constexpr uint32_t kDenseBinPoints = 8;
constexpr uint32_t kMinSectorBins = 64;

enum class Status { Ok, TooFewPoints, NoWall };

// Builds the wall grid and the floor map from src, between z_bottom_mm
// (lowest height to consider) and rim_mm; floor: the levelling's floor
// plane in src's frame.
Status build(const PointSource &src, double z_bottom_mm, double rim_mm, const Params &p,
             Workspace &ws, Model *m, const FloorPlane &floor = FloorPlane{});

struct Volume {
  double volume_mm3;
  double lo_mm3, hi_mm3;  // unseen bins bridged with the lower / higher neighbour
  double unseen_mm3;      // the part of the volume in bridged bins
  double rim_area_mm2;    // section just below the rim
  // Holes in the floor between floor seen further in and further out along
  // a ray (a wet patch on a bowl's slope): the floor there lies between
  // the height carried outward and the straight line across; the volume
  // takes the middle, this is half the difference (an interval term). Plus,
  // where a hole 20 mm or longer reaches the wall, the whole volume between
  // the carried floor and the line up to the column's lowest seen wall.
  double floor_hole_mm3;
};

// Section area per integration step, for plots and pv_session_layers():
// filled up to cap steps (bottom first) when not null.
struct Profile {
  double *z_mm;         // step centre
  double *area_mm2;
  double *seen_share;   // share of the step's wall seen or bridged short
  size_t cap;
  size_t n;
};

Volume integrate(const Workspace &ws, const Model &m, const Params &p,
                 Profile *profile = nullptr);

// Share of wall bins seen per height band (bands equal parts of 0..rim).
// Plausibility (is it one open pit?): the share of the points that lie
// well inside the void (more than margin_mm inside the wall, above the
// floor and below the rim). A pit's void holds only multipath and strays;
// a mound scanned as a pit, or two surfaces stacked, fill it. Also the
// largest wall radius, against the capacity of the grids.
//
// And the surround near the rim by height (rim_hist), for every point it
// visits: a second pass that slipped along the axis puts its copy of the
// ground ring (or a lip) a second level 8-40 mm from the first, outside the
// wall, where a single scan's surround has one level. Where the slipped
// pass is the larger, the rim is its level and the volume reaches down to
// the other pass's floor: the second level lies below the rim. The points
// counted lie more than kOutsideWallMm outside the wall grid's value at
// their height in their theta bin (a flaring wall, grooves, a bowl's lip
// stay out; the slipped rings of the tuning sweeps stay in) and, where the
// bin has a flat top (container_lip.h), inside its cap (a container's
// outer wall runs down at every height). rim_sectors: which of kRimSectors
// equal sectors around the axis each height bin's points lie in (a ring
// goes round, a protrusion's top does not).
constexpr uint32_t kRimHistBins = 48;     // 1 mm each, from rim - kRimHistBelowMm
constexpr double kRimHistBelowMm = 45.0;  // to rim + 3 mm
constexpr uint32_t kRimSectors = 36;
constexpr double kOutsideWallMm = 3.0;
struct Occupancy {
  uint64_t points;        // stored points below the rim
  uint64_t inside;        // of those, inside the void by more than margin_mm
  double max_radius_mm;   // largest seen wall radius
  double max_section_mm2; // largest section (integration step), for the mouth
  uint32_t rim_hist[kRimHistBins];
  uint64_t rim_sectors[kRimHistBins];
  // Per kRimSectors sector, the points from kWallBandFromMm to
  // kWallBandToMm above the rim within kWallBandRadiusMm of the wall's top
  // bin, and as many mm below the rim within it of the wall at their height
  // (wall_above_sectors()).
  uint32_t wall_above[kRimSectors], wall_below[kRimSectors];
  // Points within kMouthBandMm of the rim's height, and of those the ones
  // more than kMouthMarginMm inside the wall's top at their angle: over
  // the mouth, where a single scan has next to nothing (a pass slipped
  // sideways puts its ground or wall top there, over the other's void).
  uint64_t rim_level, over_mouth;
  // Per kRimSectors sector, the points from the bottom to kShiftTopMm under
  // the rim within kOnWallMm of the wall grid's value at their height and
  // angle, and those where a second copy of the wall would lie, with the
  // sum of their distances from it (shifted_wall()): around a vessel's cap
  // (Model::vessel_lip: the model keeps the inner of two walls)
  // kApartFromMm to kApartToMm behind it; elsewhere (the model keeps the
  // outer wall) up to kApartToMm in front of it, inside the void (counted
  // in inside: margin_mm in front of the wall and above the floor).
  uint32_t on_wall[kRimSectors], apart[kRimSectors];
  double apart_mm[kRimSectors];
};
constexpr double kMouthBandMm = 1.5;
constexpr double kMouthMarginMm = 5.0;

// A second level in the surround (Occupancy::rim_hist): the most prominent
// 3 mm of height centred 8 to 40 mm below the rim (its points less three
// times the mean mm from 3 to 6 mm below or above it, the higher: a peak,
// not the step where a wall ends) against the most prominent 3 mm centred
// from 5 mm below the rim to 2 mm above it (less the same below it).
struct SecondLevel {
  double ratio;            // second / top; 0 without a top
  double points;           // the second level's prominence, points
  double sigma;            // points over the noise of its sides' count
  double below_rim_mm;     // its height under the rim (centre of the 3 mm)
  uint32_t sectors, top_sectors;  // sectors its points / the top's lie in
};
SecondLevel second_level(const Occupancy &o);
// A pass slipped sideways by more than the ghost window (ghost_mm): the
// other pass's wall lies apart from the model's by the shift times |cos|
// of the angle to it, two opposite sides at the full shift and none across
// them. Where the two wall tops were read as a vessel's lip, capped there,
// the model keeps the inner of the two walls all round (the pits'
// intersection) and the other lies behind it; elsewhere the model keeps
// the outer (their union) and the other lies in front of it, in the void.
// A vessel's outer wall lies behind its inner one by about the lip's width
// all round. share: the points apart over those on the wall; fit: the
// squared residual of the sectors' mean distances apart (0 for a sector
// with under kMinApartPoints or kMinApartShare of its wall's points) about
// D |cos(angle - a)| at the best a and D, over their residual about their
// mean (1 where all are equal); offset_fit and shift_mm: the same about
// c + D |cos(angle - a)| with D > 0 (the distances nearest across the
// shift are cut off at kApartFromMm, or at the inside margin, and a
// textured wall's own relief adds to all) and its D (1 and 0 where no
// D > 0 fits).
constexpr double kOnWallMm = 1.5, kApartFromMm = 3.0, kApartToMm = 40.0, kShiftTopMm = 3.0;
constexpr uint32_t kMinApartPoints = 5;
constexpr double kMinApartShare = 0.05;
struct ShiftedWall {
  double share, fit, offset_fit, shift_mm;
};
ShiftedWall shifted_wall(const Occupancy &o);
// The wall going on above the rim: the sectors with kMinWallAbovePoints or
// more points over the rim at the wall's top, at least kMinWallAboveShare
// of the points as far under it on the wall. A rim found below the top of
// the wall (its top band seen thinly, a dense ledge under it) cuts the pit
// there: a grooved rounded bowl's rim 16 mm low read -14.1 % with PV_OK.
constexpr double kWallBandFromMm = 3.0, kWallBandToMm = 13.0, kWallBandRadiusMm = 5.0;
constexpr uint32_t kMinWallAbovePoints = 3;
constexpr double kMinWallAboveShare = 0.1;
uint32_t wall_above_sectors(const Occupancy &o);
Occupancy occupancy(const PointSource &src, const Workspace &ws, const Model &m,
                    const Params &p, double margin_mm);

// The floor's second level with each stored point weighed by what it
// stands for (its bin's thinning, 2^level): a pass slipped along the axis
// puts its floor in layers of their own, which thin as a wall's layer does
// (a 1024-point bin for the whole section), while the first pass's floor
// lies in the floor store, thinned as one. Counted point by point (Model::
// floor_far_points), a textured pit's second floor 23 mm up held 1757
// points against 52,240 on the floor, 0.03 (fresh seed 1310 #259: +15.5 %
// with PV_OK); weighed, about as many as the floor. Over the flooded floor
// cells away from the wall's foot (the cells' states after build()):
// within Params::band_mm of a cell's floor (floor), and from band + ghost_mm
// to band + slip_mm above it (far, in 1 mm height bins from the window's
// bottom: hist; the same bins as the model's own far histogram).
constexpr uint32_t kFloorSlipBins = 32;
struct FloorWeights {
  double floor = 0, far = 0;
  double hist[kFloorSlipBins] = {};
  double z_top = 1e300;  // no point above it counts (the highest floor cell's window)
  // The share of far within its densest 3 mm of height.
  double far_peak() const;
};
// Empty counts, and z_top from the flooded cells (most of a scan's points,
// the wall's, then cost one comparison).
FloorWeights start_floor_weights(const Workspace &ws, const Model &m, const Params &p);
// Adds n levelled points, each standing for weight points of the scan.
void weigh_floor(const Workspace &ws, const Model &m, const Params &p, const Point *pts, size_t n,
                 double weight, FloorWeights *acc);

// "Seen" counts bins bridged over at most short_gap_bins.
void coverage(const Workspace &ws, const Model &m, const Params &p, uint32_t bands, float *out);

}  // namespace pv::surface

#endif
