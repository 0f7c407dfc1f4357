// Procedural test pits with an exactly known void volume.
//
// A pit lives in its own frame: the axis on Z, the floor around z = 0, the
// rim (ground) plane at z = rim_z_mm. Two triangle meshes describe it:
// - scanned: what a scanner can see: wall, floor, and the ground ring around
//   the rim when the pit has one;
// - void_closed: the void below the rim plane, closed by a lid in the rim
//   plane. Its signed volume (divergence theorem) is the ground truth: exact
//   for the very surface the scanner rays hit, independent of any slicing.
// Both meshes share the wall and floor vertices, so the truth and the scan
// describe one surface. Everything is deterministic in (family, ground, seed).
#ifndef PV_SIM_PIT_GEOMETRY_H
#define PV_SIM_PIT_GEOMETRY_H

#include <cstdint>
#include <string>
#include <vector>

namespace pv::sim {

struct Mesh {
  std::vector<float> xyz;     // 3 floats per vertex, millimetres
  std::vector<uint32_t> tri;  // 3 vertex indices per triangle, counter-
                              // clockwise seen from outside the void
  size_t vertices() const { return xyz.size() / 3; }
  size_t triangles() const { return tri.size() / 3; }
};

enum class Family {
  Cylinder = 0,  // smooth, like the paper's device: ~22 cm across, 29 cm deep
  Protrusions,   // cylinder with 4-8 blocks of 1-3 cm on the wall
  Textured,      // 5 mm lining with transverse grooves (tool marks)
  Tapered,       // wide top, narrow bottom
  Bowl,          // rounded bottom
  Necking,       // narrower at mid-depth (overhang seen from above)
  Bulge,         // local over-excavation
  Elliptical,    // elliptical section
  HandDug,       // radius varies with angle and depth, uneven bottom
  ShallowWide,   // 40 cm across, 10 cm deep
  DeepNarrow,    // 15 cm across, 40 cm deep
  kCount
};

const char *family_name(Family f);           // "cylinder", "protrusions", ...
bool family_from_name(const std::string &name, Family *out);

struct Pit {
  Family family;
  bool ground;             // a ring of surrounding ground at the rim plane
  uint64_t seed;
  Mesh scanned;
  Mesh void_closed;
  double volume_mm3;       // signed volume of void_closed
  double rim_z_mm;         // the rim (ground) plane
  double max_radius_mm;    // largest wall radius (scan path planning)
  double ground_outer_radius_mm;  // 0 without ground
  std::string params_json; // the drawn parameters, a JSON object, for manifests
};

// Parameters are drawn from the seed within the family's ranges.
Pit make_pit(Family f, bool ground, uint64_t seed);

double signed_volume_mm3(const Mesh &m);

}  // namespace pv::sim

#endif
