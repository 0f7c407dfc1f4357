// A reference 2.5D grid volume: what CloudCompare's "2.5D volume" does, as
// a yardstick for pitvol's own methods in the accuracy report
// (docs/accuracy.md "Peers").
//
// Input: a levelled cloud (bottom plane at z = 0, the pit opening towards
// +z, millimetres) and the rim height (the lid plane). Steps:
//  1. The rim outline, in polar form around the pit axis (the median XY of
//     the points below half the depth): per 1 deg sector, the third largest
//     radius of the points in the band from rim - 10 mm to rim - 1 mm (the
//     top of the wall; the third, so that two strays cannot widen it).
//     Sectors without three points there take their neighbours' radius.
//  2. A grid of cell_mm cells over the outline; a cell is in the pit when
//     its centre is inside the outline (interpolated between sectors).
//  3. Each cell's height is the mean z of the points that fall in it
//     (CloudCompare's default; the median is a diagnostic option: it shows
//     how much of the error is multipath points floating above a surface).
//  4. Empty cells in the pit are filled from their neighbours: passes in
//     which every empty cell with filled 8-neighbours takes their mean,
//     until none is left.
//  5. volume = sum over pit cells of (rim - height) * cell area. Not clipped
//     at zero: ground noise above and below the rim cancels, as in
//     CloudCompare's "added - removed" total.
// Why hand-written: CloudCompare's grid is part of a Qt application, not a
// library we can link; the whole method is a few dozen lines.
#ifndef PV_PEERS_GRID25_H
#define PV_PEERS_GRID25_H

#include <cstdint>
#include <string>
#include <vector>

namespace pv::peers {

struct LevelledPoint {
  float x_mm, y_mm, z_mm;
};

struct Grid25Params {
  double cell_mm = 1.0;
  uint32_t sectors = 360;
  double band_top_mm = 1.0;     // band of the wall top: rim - 10 .. rim - 1
  double band_depth_mm = 10.0;
  bool median = false;          // cell height: median z instead of the mean
};

struct Grid25Result {
  bool ok = false;
  std::string error;            // why not, when !ok
  double volume_cm3 = 0;
  uint64_t pit_cells = 0;       // cells inside the outline
  uint64_t filled_cells = 0;    // of those, filled from neighbours
  double outline_area_mm2 = 0;
  uint32_t empty_sectors = 0;   // outline sectors interpolated
};

Grid25Result grid25_volume(const std::vector<LevelledPoint> &pts, double rim_mm,
                           const Grid25Params &p);

// Reads a cloud written by `pitvol measure --export-levelled`: binary little
// endian PLY with float x, y, z and the comment "pitvol_rim_mm <value>".
bool read_levelled_ply(const std::string &path, std::vector<LevelledPoint> *pts,
                       double *rim_mm, std::string *err);

}  // namespace pv::peers

#endif
