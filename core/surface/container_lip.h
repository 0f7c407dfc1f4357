// The outer edge of a flat top around the pit: a container's lip (or the
// ground ring's far edge), per theta bin of the wall grid.
//
// A container is scanned from inside and, for part of the path, from
// outside: its outer wall then lies a lip's width behind the inner wall,
// in the same wall bins, and a bin's largest radius reads the outer wall
// (the DOUBLED_WALL and POINTS_INSIDE refusals, and volumes up to +35 %,
// of containers in the envelope sweeps, docs/accuracy.md). Nothing below a
// flat top and beyond its outer edge can be the pit: the wall seen through
// the mouth lies inside the top's edge, the outer wall at it. So where the
// top band (within kLipBandMm of the rim plane) of a theta bin is flat,
// points below it from kLipTolMm inside its outer edge outward stay out of
// the wall grid.
#ifndef PV_SURFACE_CONTAINER_LIP_H
#define PV_SURFACE_CONTAINER_LIP_H

#include <cstddef>

#include "surface/surface_model.h"

namespace pv::surface {

constexpr double kLipBandMm = 1.0;  // top band: this close to the rim plane
constexpr double kLipTolMm = 1.5;   // cap this far inside the top's outer edge
// A theta bin's top is flat (a lip or a ground ring, not the top of a wall
// that ends at the rim) when this share of its top band points lies
// further in than kLipTolMm from its outer edge: a 3 mm lip holds half of
// its points there, a vertical wall's top none, a 45 deg wall's a quarter
// over the band's 2 mm (and a sloping wall is not undercut there).
constexpr double kLipFlatShare = 0.3;
// And the top is a ring round the mouth, not a disc: its inner edge lies
// at least this share of the outer edge's radius out (a closed shell's top
// is a disc, and capping at its edge would drop the shell's wall, which
// the mouth check refuses).
constexpr double kLipMinHole = 0.5;
// And the top reaches out over nothing: under half of the wall points
// within kLipBelowMm under the rim lie further out than kLipTolMm beyond
// its outer edge (a dome or a necking top reaches in over a wider wall; a
// container's outer wall stands at the edge).
constexpr double kLipBelowMm = 6.0;
// And the ring is one surface, not two wall tops side by side (a pass
// that slipped sideways shows the wall twice): this share of its top band
// points lies in the middle half of the ring (a lip's surface spans it).
constexpr double kLipMidShare = 0.05;
// A bin with fewer top band points than kLipMinPoints pools them
// from up to kLipMaxReach bins either side.
constexpr unsigned kLipMinPoints = 6;
constexpr int kLipMaxReach = 3;
// Where the flat bins' median width is a vessel's lip (at most
// kLipMaxWidthMm; the simulator's lips are 3-15 mm, its ground rings 40 mm
// and more), a bin that is not flat takes its cap from the nearest flat bins
// within kLipFillReachDeg either side (container_lip.cpp says why). A wider
// ring (a ground, or a vessel's top reaching out over a bulge) is capped
// only where the wall below shows an outer wall.
constexpr double kLipMaxWidthMm = 20.0;
// A flat ring wider than a lip: a ground, or a vessel's top reaching out
// over a bulge (lip_caps() leaves its round undecided; the grid counts the
// outer wall's evidence near its caps only: surface_model.cpp).
constexpr bool wide_ring(double width_mm) { return width_mm > kLipMaxWidthMm; }
constexpr double kLipFillReachDeg = 30.0;
constexpr uint32_t kLipFillMinBins = 180;  // 2 deg bins or finer
// Under half of the round flat, the round may still be a vessel's where
// its flat bins are at least this share of the bins with a top and their
// median width a wall's (the simulator's lips are 3-15 mm; a wall's top
// that looks flat in a bin or two spans a tenth of a millimetre).
constexpr double kLipMinFlatShare = 0.05;
constexpr double kLipMinWidthMm = 1.0;
// and the quarter widest flat bins at most this many times their median
// width (the 75th percentile).
constexpr double kLipMaxWidthSpread = 2.5;

// cap[t] for each of the wall grid's theta bins around m.axis: points
// below the top band with a radius of cap[t] or more are outside the pit
// (HUGE_VALF: no flat top in that bin, no cap). scratch: 14 * theta_bins
// floats. Two passes over the points of the top band.
// Where under half of the round's top is flat but the flat bins' width is
// a vessel's, cap holds the flat bins only and vessel_cap (theta_bins
// floats) the whole round as a vessel's (the flat bins' caps carried round):
// returns true, and the grid decides from the wall below which it is
// (surface_model.cpp, kOuterWallShare). So too where the flat bins' width
// is wider than a vessel's lip, on bins of 2 deg or finer: then cap holds
// nothing. vessel_lip: most capped bins'
// flat top (of the vessel's caps where the round is undecided), from the
// bin's inner edge out to the cap's edge, is kLipMaxWidthMm wide or
// narrower (Model::vessel_lip).
struct LipCaps {
  bool undecided = false;
  bool vessel_lip = false;
  float width_mm = 0;  // where undecided: the flat bins' median width
};
LipCaps lip_caps(const PointSource &src, const Workspace &ws, const Model &m, float *cap,
                 float *vessel_cap, float *scratch);

}  // namespace pv::surface

#endif
