/*
 * pitvol core — C ABI.
 *
 * A measuring session lives in one memory block that the caller provides.
 * The caller asks how many bytes a configuration needs, hands over a block
 * of that size, pushes point batches while the scan runs, may ask for a
 * running estimate, and calls finish() for the result.
 *
 *   pv_config_t cfg;  pv_config_default(&cfg);
 *   size_t n = 0;     pv_session_size(&cfg, &n);
 *   void *block = aligned_alloc(PV_BLOCK_ALIGN, n);
 *   pv_session_t *s;  pv_session_init(&cfg, block, n, &s);
 *   pv_session_push(s, pts, count);   ... many times ...
 *   pv_result_t r;    pv_session_finish(s, &r);
 *   pv_session_reset(s);              next scan, same block
 *
 * No function allocates on the ingest path (push). estimate() and finish()
 * use only the block, except the kNN index of adaptive thinning, whose
 * bounded scratch is documented in docs/memory.md. No exception crosses
 * this ABI: every failure is a pv_status_t with a name and a message.
 *
 * Coordinates are millimetres in the scanner's frame (any pose, any tilt).
 */
#ifndef PITVOL_PITVOL_H
#define PITVOL_PITVOL_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_VERSION_STRING "0.1.0"
#define PV_BLOCK_ALIGN 64u

typedef enum pv_status {
  PV_OK = 0,
  PV_ERR_INVALID_ARGUMENT = 1,   /* NULL pointer or a value out of range */
  PV_ERR_INVALID_CONFIG = 2,     /* a configuration field is out of range */
  PV_ERR_BLOCK_TOO_SMALL = 3,    /* block smaller than pv_session_size() */
  PV_ERR_BLOCK_MISALIGNED = 4,   /* block not aligned to PV_BLOCK_ALIGN */
  PV_ERR_WRONG_STATE = 5,        /* e.g. push after finish without reset */
  PV_ERR_TOO_FEW_POINTS = 6,     /* scan has too few valid points */
  PV_ERR_NO_BOTTOM_PLANE = 7,    /* no plane found to level the scan */
  PV_ERR_NO_RIM = 8,             /* rim (top edge) could not be found */
  PV_ERR_TOO_FEW_LAYERS = 9,     /* too few layers with a usable contour */
  PV_ERR_DEPTH_EXCEEDS_CAPACITY = 10, /* pit deeper than max_depth_mm */
  PV_ERR_OUT_OF_MEMORY = 11,     /* bounded finish scratch unavailable */
  PV_ERR_INTERNAL = 12,          /* a bug: please report with the scan */
  PV_ERR_WALL_GAP = 13,          /* a band of wall has no usable contour */
  PV_ERR_NOT_A_PIT = 14          /* the points do not look like one pit */
} pv_status_t;

/* Short symbolic name ("PV_ERR_NO_RIM") and a sentence for the user that
 * says what went wrong and what to do. Never NULL. */
const char *pv_status_name(pv_status_t status);
const char *pv_status_message(pv_status_t status);

/* Which plausibility check refused a scan as PV_ERR_NOT_A_PIT
 * (pv_result_t.failed_check, with the measured figure and its limit). */
typedef enum pv_pit_check {
  PV_PIT_CHECK_NONE = 0,          /* passed, or the status is not NOT_A_PIT */
  PV_PIT_CHECK_NO_POINTS = 1,     /* no point near the modelled surface */
  PV_PIT_CHECK_POINTS_INSIDE = 2, /* value: share of the points inside the
                                     void the wall encloses; limit: the most
                                     a pit holds (strays, multipath) */
  PV_PIT_CHECK_NARROW_MOUTH = 3,  /* value: the section at the rim over the
                                     largest section; limit: the least an open
                                     pit shows */
  PV_PIT_CHECK_TOO_WIDE = 4,      /* value: the widest wall radius, mm; limit:
                                     the grids' radius (surface_max_radius_mm)
                                     less a margin */
  PV_PIT_CHECK_OPENING_TILT = 5,  /* value: the opening's tilt from the
                                     scanner's view, deg; limit:
                                     max_opening_tilt_deg */
  PV_PIT_CHECK_SECTIONS = 6,      /* per-layer methods (paper, polar): value:
                                     the volume over the largest kept section
                                     times the depth; limit: 1.05 (sections
                                     between 0 and the largest bound it to
                                     [0, 1], plus the ends' extrapolation;
                                     outside, or not above 0, the sequence is
                                     too erratic to integrate) */
  PV_PIT_CHECK_DOUBLED_WALL = 7,  /* value: of the well-seen wall bins, the
                                     share with a second wall a few mm behind
                                     the first (or within its band) on two
                                     opposite sides, less
                                     the share across them (two copies a
                                     rigid shift apart); limit: the most a
                                     single scan shows */
  PV_PIT_CHECK_DOUBLED_FLOOR = 8, /* value: the share of the floor's points a
                                     few mm above it; limit: the most a
                                     single scan shows */
  PV_PIT_CHECK_TOO_SMALL = 9,     /* value: the volume, cm3; limit: the
                                     smallest test hole (below the standards'
                                     smallest: a scan in cm or m read as mm) */
  PV_PIT_CHECK_DOUBLED_RIM = 10,  /* value: the points of the surround
                                     (ground ring or lip) on a second level
                                     8-40 mm under the rim over those at the
                                     rim; limit: the most a single scan
                                     shows */
  PV_PIT_CHECK_THIN_TOP = 11,     /* value: the wall's points per mm of
                                     height from a step 6-42 mm under the
                                     rim up to it, over those in the 20 mm
                                     below the step (the top seen by one
                                     pass of two slipped apart in height);
                                     limit: the least a single scan shows */
  PV_PIT_CHECK_OVER_MOUTH = 12,   /* value: the share of the points at the
                                     rim's height that lie over the mouth,
                                     5 mm or more inside the wall's top (a
                                     pass slipped sideways: its ground or
                                     wall top over the other's void); limit:
                                     the most a single scan shows */
  PV_PIT_CHECK_SHIFTED_WALL = 13, /* value: the share of the wall's points
                                     lying 3-40 mm behind it, where their
                                     distance round the wall follows one
                                     sideways shift (a pass slipped sideways
                                     past 8 mm, its two wall tops read as a
                                     vessel's lip); limit: the most a single
                                     scan shows with such a pattern */
  PV_PIT_CHECK_DOUBLED_SPARSE_WALL = 14 /* a wall too sparse for
                                     DOUBLED_WALL's contrast (the smallest
                                     pits): value: the share of its 10 deg
                                     sectors holding a tenth of their points
                                     or more a few mm behind the wall (a
                                     second pass shifted sideways puts them
                                     there over most of the wall); limit:
                                     the most a single scan shows */
} pv_pit_check_t;
/* "PV_PIT_CHECK_POINTS_INSIDE", ... */
const char *pv_pit_check_name(uint32_t check);
/* What the check found, in words, without the numbers ("points lie inside
 * the pit's void"). */
const char *pv_pit_check_message(uint32_t check);

typedef enum pv_method {
  PV_METHOD_PAPER = 0, /* Han et al., Sensors 2026, 26(10), 3150 */
  PV_METHOD_POLAR = 1, /* paper, with a trimmed Fourier r(theta) area per
                          layer instead of clustering + y(x) cubics */
  PV_METHOD_SURFACE = 2 /* one surface over the whole pit: wall radius grid
                           R(theta, z) around a leaning axis + floor height
                           map (docs/method.md) */
} pv_method_t;

/* "paper" / "polar" / "surface" <-> the enum. PV_ERR_INVALID_ARGUMENT if unknown. */
PV_NODISCARD pv_status_t pv_method_from_name(const char *name, pv_method_t *out);
const char *pv_method_name(pv_method_t method);

typedef struct pv_config {
  pv_method_t method;

  /* capacities: fixed at init, they size the block */
  uint32_t max_layers;          /* layer bins; depth range = max_layers*layer_mm */
  uint32_t points_per_layer;    /* bin capacity; a full bin thins in place */
  uint32_t level_sample_points; /* order-independent sample for levelling */
  uint32_t warmup_points;       /* points buffered before the first plane */

  /* Z gridding (paper 3.4) */
  float layer_mm;               /* 0.5 by default; 0.1 .. 2 allowed */

  /* levelling (paper 3.2, Algorithm 1) */
  float bottom_band_ratio;      /* beta: bottom candidates within beta*z-range */
  float plane_tol_ratio;        /* alpha: d_max = alpha * extent */
  uint32_t ransac_iterations;

  /* rim (paper 3.3) */
  float rim_band_ratio;         /* top candidates within this share of z-range */

  /* adaptive thinning (paper 3.5) */
  uint32_t knn_k;
  float thin_base_mm;           /* s0 */

  /* clustering (paper 3.6) */
  float crescent_range_mm;      /* 50 */
  float crescent_cross_mm;      /* 80 */
  float circle_band_mm;         /* 20 */
  float crescent_relax_mm;      /* 10 */

  /* area sequence cleanup (paper 4.2, Algorithm 2) */
  uint32_t mad_window_early;    /* 10 */
  uint32_t mad_window_late;     /* 6 */
  float mad_k_early;
  float mad_k_late;
  float mad_split_mm;           /* 30: late segment = last 30 mm above bottom */

  /* method surface (docs/method.md) */
  float max_unseen_share;       /* refuse (PV_ERR_WALL_GAP) when more of the
                                   volume than this rests on unseen wall */
  uint32_t duplicate_filter;    /* 1: drop resent points (a fixed 1 MiB of
                                   the block, docs/reliability.md); 0: none
                                   (the MCU profile, whose block is 512 KB) */
  float max_opening_tilt_deg;   /* the pit's opening must face within this
                                   angle of the scanner frame's +Z (up, away
                                   from the ground); else PV_ERR_NOT_A_PIT (a
                                   mound). 180: a frame that may be upside
                                   down, no check */
  /* method surface: capacities of the surface model (docs/memory.md; the
     MCU profile shrinks them to fit its 512 KB block, docs/targets.md) */
  uint32_t surface_floor_points;  /* floor band store, points (65536) */
  uint32_t surface_theta_bins;    /* wall grid: angle bins (180: 2 deg) */
  float surface_wall_dz_mm;       /* wall grid: bin height (2) */
  float surface_cell_mm;          /* floor map: cell side (2) */
  float surface_max_radius_mm;    /* widest pit around its axis (320) */
  float surface_band_mm;          /* wall surface band behind a bin's largest
                                     radius (1.5; wider for wider bins) */
  uint32_t surface_coarse_bins;   /* 1: wall bins too coarse for their few
                                     points (the MCU profile): a sparse bin
                                     borrows its slope along the angle, the
                                     floor flood allows the default's slope,
                                     and the interval counts what the bins
                                     cannot resolve (docs/targets.md). 0 */
} pv_config_t;

/* Fills the default configuration: method surface, the paper's values where
   it gives them, and the default capacities (docs/method.md). */
void pv_config_default(pv_config_t *cfg);
/* The block budget of a microcontroller build: the MCU profile's block fits
 * in it (firmware/mcu's linker script reserves exactly this much). */
#define PV_MCU_BLOCK_BYTES (512u * 1024u)
/* The MCU profile: pv_config_default() with the capacities, grids and layer
 * height changed so that the block fits PV_MCU_BLOCK_BYTES (docs/memory.md;
 * its accuracy against the default: docs/targets.md). Every other method
 * parameter keeps its default. */
void pv_config_mcu(pv_config_t *cfg);
/* PV_OK or PV_ERR_INVALID_CONFIG; if field_out is not NULL it receives the
 * name of the first offending field. */
PV_NODISCARD pv_status_t pv_config_validate(const pv_config_t *cfg, const char **field_out);

typedef struct pv_point {
  float x_mm, y_mm, z_mm;
} pv_point_t;

/* Warning bits of a result or estimate. */
#define PV_WARN_POINTS_THINNED   (1u << 0) /* a layer bin overflowed and thinned */
#define PV_WARN_INVALID_POINTS   (1u << 1) /* NaN/Inf or absurd points skipped */
#define PV_WARN_OUT_OF_RANGE     (1u << 2) /* points outside the layer range */
#define PV_WARN_LAYERS_REJECTED  (1u << 3) /* many layers removed by cleanup */
#define PV_WARN_LARGE_TILT       (1u << 4) /* scan tilted more than 30 deg */
#define PV_WARN_SPARSE_LAYERS    (1u << 5) /* many layers had too few points */
#define PV_WARN_BRIDGED          (1u << 6) /* an unseen band of wall was bridged
                                              from its neighbours (see
                                              unseen_share, coverage) */
#define PV_WARN_ALL              0x7Fu     /* every bit defined above */

/* The PV_WARN_* bits in words, from one table (core/session/status.cpp)
 * for every tool and screen: the symbolic name ("PV_WARN_BRIDGED"), a
 * sentence that says what happened and what to do, and a short form for a
 * line of a 320-px screen (at most 24 characters). NULL for a bit that is
 * not defined. */
const char *pv_warning_name(uint32_t bit);
const char *pv_warning_message(uint32_t bit);
const char *pv_warning_short(uint32_t bit);
/* The bits of a result's warnings that need the user's attention; the
 * other set bits are notes, shown as information. Never
 * PV_WARN_POINTS_THINNED: the fixed memory thins the dense bins of every
 * ordinary scan by design, and the accuracy figures include it. Not
 * PV_WARN_BRIDGED while less than PV_WARN_BRIDGED_SHARE of the volume
 * rests on unseen wall: short bridges an ordinary scan has, inside the
 * interval. */
#define PV_WARN_BRIDGED_SHARE 0.01
uint32_t pv_warnings_attention(uint32_t warnings, double unseen_share);

/* Wall coverage: the depth from the bottom (0) to the rim is split into
 * this many equal bands; coverage[b] is the share of band b's wall that the
 * scan saw (0..1), b = 0 at the bottom. */
#define PV_COVERAGE_BANDS 16

typedef struct pv_result {
  pv_status_t status;
  double volume_cm3;
  double depth_mm;          /* bottom plane to rim */
  double tilt_deg;          /* angle of the levelled frame's up from scanner +Z:
                               the bottom normal (paper, polar), the opening's
                               normal (surface) */
  double rim_area_mm2;      /* cross-section of the highest kept layer */
  double gap_from_mm;       /* widest band without a usable contour, */
  double gap_to_mm;         /* heights above the bottom (0, 0 if none) */
  uint32_t layers_used;
  uint32_t layers_rejected; /* negative/outlier areas and unusable layers */
  uint64_t points_in;       /* every point pushed */
  uint64_t points_invalid;  /* NaN/Inf/absurd, skipped */
  uint64_t points_out_of_range;
  uint64_t points_stored;   /* held in the bins at the end */
  uint64_t points_used;     /* kept by thinning + clustering, fed to area fits */
  uint32_t warnings;        /* PV_WARN_* bits */
  /* Uncertainty: the true volume lies in volume_cm3 +/- interval_cm3 (a
   * bound from fit residuals, levelling, rim and unseen bands; 0 when the
   * method cannot say). */
  double interval_cm3;
  double unseen_share;      /* share of the volume in bridged, unseen wall */
  uint32_t coverage_bands;  /* bands filled in coverage[] (0 if no rim) */
  float coverage[PV_COVERAGE_BANDS];
  /* PV_ERR_NOT_A_PIT: which check refused (pv_pit_check_t), the figure it
   * measured and the limit it was held to; PV_PIT_CHECK_NONE, 0, 0 else. */
  uint32_t failed_check;
  double check_value;
  double check_limit;
} pv_result_t;

typedef struct pv_session pv_session_t;

/* Bytes of block a configuration needs. */
PV_NODISCARD pv_status_t pv_session_size(const pv_config_t *cfg, size_t *bytes_out);
/* Carves the session out of block; *session_out points into block. */
PV_NODISCARD pv_status_t pv_session_init(const pv_config_t *cfg, void *block, size_t bytes,
                                         pv_session_t **session_out);
/* Any batch size (0 allowed), any order. Never allocates. */
PV_NODISCARD pv_status_t pv_session_push(pv_session_t *s, const pv_point_t *points,
                                         size_t count);
/* Volume from what has arrived so far; the session keeps streaming.
 * PV_ERR_TOO_FEW_POINTS until warmup_points have arrived (the first plane
 * is fitted then; an estimate never changes the final result). */
PV_NODISCARD pv_status_t pv_session_estimate(pv_session_t *s, pv_result_t *out);
/* Final result. The session accepts no more points until reset. */
PV_NODISCARD pv_status_t pv_session_finish(pv_session_t *s, pv_result_t *out);
/* Forget the scan, keep the configuration and the block. */
PV_NODISCARD pv_status_t pv_session_reset(pv_session_t *s);

/* Per-layer detail of the last estimate/finish, for plots and reports.
 * Writes at most capacity entries, returns the count in *count_out. */
typedef struct pv_layer_info {
  float z_mm;        /* height above the bottom plane */
  float area_mm2;
  uint32_t points;   /* points fed to the area fit */
  uint8_t kept;      /* 0 if removed by cleanup or unusable */
  uint8_t shape;     /* 0 near-circular, 1 crescent */
} pv_layer_info_t;
PV_NODISCARD pv_status_t pv_session_layers(const pv_session_t *s, pv_layer_info_t *out,
                                           size_t capacity, size_t *count_out);

/* The levelling and the lid of the last estimate/finish, for tools that
 * measure the same levelled cloud another way (the peers of the accuracy
 * report, exports). Computed as measure() does: the final levelling fit on
 * the order-independent sample, then the rim (ground peak, else wall top).
 *   p_levelled = rotation * p_raw + translation_mm   (rotation row-major)
 * The bottom plane is at levelled z = 0, the pit opens towards +z. Returns
 * the levelling's failure status (nothing filled), or PV_ERR_NO_RIM with
 * the transform filled and rim_mm < 0, else PV_OK. Uses only the block. */
typedef struct pv_transform {
  double rotation[9];
  double translation_mm[3];
  double rim_mm;        /* rim height above the bottom plane */
  uint32_t rim_from_ground; /* 1: ground ring peak, 0: top of the wall */
} pv_transform_t;
PV_NODISCARD pv_status_t pv_session_transform(pv_session_t *s, pv_transform_t *out);

/* The surface model's wall grid (method surface), for plots and reports:
 * the wall's radius around the pit's axis on theta_bins x z_bins bins, in
 * the levelled frame of pv_session_transform() (bottom plane at z = 0).
 * Bin (t, k) is entry k * theta_bins + t: angle centre (t + 0.5) * 360 /
 * theta_bins degrees (atan2(y - axis_y, x - axis_x), counter-clockwise
 * from +x), height centre z0_mm + (k + 0.5) * dz_mm. The axis leans: its
 * centre at height z is (axis_x_mm + axis_dx * z, axis_y_mm + axis_dy * z).
 * radius_mm holds the wall radius the volume is integrated with (bridged
 * where unseen); state one PV_WALL_* per bin. Rebuilt from the points
 * stored so far as finish() builds it (after finish: the grid the volume
 * was integrated over); uses only the block, like pv_session_transform().
 * With radius_mm and state NULL only grid is filled; else capacity must
 * hold theta_bins * z_bins entries (PV_ERR_INVALID_ARGUMENT otherwise,
 * grid filled). PV_ERR_WRONG_STATE for the per-layer methods (paper,
 * polar), which have no wall grid. */
#define PV_WALL_NONE 0          /* no value (nothing seen around it) */
#define PV_WALL_SEEN 1          /* the scan saw this wall */
#define PV_WALL_FLOOR 2         /* floor points: the floor map bounds the void */
#define PV_WALL_SHORT_BRIDGE 3  /* bridged over a short gap: counts as seen */
#define PV_WALL_UNSEEN 4        /* not seen, bridged from around (interval) */
typedef struct pv_wall_grid {
  double axis_x_mm, axis_y_mm; /* the axis at z = 0 */
  double axis_dx, axis_dy;     /* its lean, mm per mm of height */
  double z0_mm, dz_mm;         /* bottom of the grid, bin height */
  double rim_mm;               /* rim height (as pv_result_t.depth_mm) */
  uint32_t theta_bins, z_bins;
} pv_wall_grid_t;
PV_NODISCARD pv_status_t pv_session_wall_grid(pv_session_t *s, pv_wall_grid_t *grid,
                                              float *radius_mm, uint8_t *state,
                                              size_t capacity);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_PITVOL_H */
