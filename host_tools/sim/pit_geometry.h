// Procedural test pits with an exactly known void volume.
//
// A pit lives in its own frame: the axis on Z, the floor around z = 0, the
// rim (ground) plane at z = rim_z_mm. Two triangle meshes describe it:
// - scanned: what a scanner can see: wall, floor, and the ground ring around
//   the rim when the pit has one;
// - void_closed: the void below the rim plane, closed by a lid in the rim
//   plane (with PitOptions::ground_tilt_deg, below the tilted ground plane,
//   the lid being that plane). Its signed volume (divergence theorem) is the
//   ground truth: exact for the very surface the scanner rays hit,
//   independent of any slicing.
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
  RoundedBowl,   // half-ellipsoid under a short vertical wall: no flat floor
  kCount
};

// The 11 families of the corpus sets (standard, holdout, stress): the corpus
// iterates these only, so a family added after them (RoundedBowl) leaves the
// corpus's scans, and tests/corpus/expected.csv, byte for byte the same.
constexpr int kCorpusFamilies = 11;

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
  // The last ground_triangles triangles of `scanned` are the ground ring
  // (0 without ground) or a container's lip. The scan sees them from above
  // even when the ring is tilted out of the rim plane.
  size_t ground_triangles = 0;
  // What surrounds the rim: "ground" (the ring), "none", or "container"
  // (PitOptions::container_lip_mm: a flat lip and an outer wall going down).
  std::string surround;
  double lip_outer_radius_mm = 0.0;  // container only: largest lip radius
};

// Departures from a family's drawn shape, for the stress corpus. The
// defaults change nothing: make_pit(f, g, s, PitOptions()) is bit-identical
// to the pits of the standard corpus.
struct PitOptions {
  // The ground surface tilted against the floor: the ground (and the lid of
  // void_closed, which IS the ground surface) is the plane
  //   z = rim_z_mm + tan(tilt) * (x cos(azimuth) + y sin(azimuth)),
  // through the rim height on the axis. The wall is sheared in z only
  // (z += (t / depth) * plane offset at the vertex's x, y), so it keeps its
  // cross-sections, still meets the floor at t = 0 and ends on the plane.
  // The truth is the void below that plane and above the floor.
  double ground_tilt_deg = 0.0;
  double ground_tilt_azimuth_rad = 0.0;
  // Depth (rim plane height above the floor), replacing the family's draw;
  // 0 keeps it. Cylinder-like families only (cylinder, shallow_wide,
  // deep_narrow): make_pit throws std::invalid_argument for the others.
  double depth_mm = 0.0;
  // A stone on the floor: a raised-cosine bump of height stone_height_mm and
  // base radius stone_radius_mm centred at (stone_x_mm, stone_y_mm):
  //   dz(d) = H (1 + cos(pi d / a)) / 2 for d < a,
  // volume pi H a^2 (1/2 - 2/pi^2). The void excludes it. 0 height: none.
  // Families with a floor grid only (all but bowl), and the bump must clear
  // the wall by 2 mm (else std::invalid_argument).
  double stone_height_mm = 0.0;
  double stone_radius_mm = 0.0;
  double stone_x_mm = 0.0, stone_y_mm = 0.0;

  // The options below serve the envelope sweeps (sim/envelope.h); their
  // defaults change nothing either.
  //
  // Size: the family's drawn shape stretched by scale_xy across and
  // scale_z along the axis (ring heights, radii and floor relief alike),
  // before grooves and stones are added in millimetres.
  double scale_xy = 1.0, scale_z = 1.0;
  // More stones and loose lumps on the floor, each a raised-cosine bump as
  // the stone above (heights may overlap: they add). The same conditions:
  // flat-floor families only, clear of the wall by 2 mm. The void
  // excludes them.
  struct Bump {
    double height_mm, radius_mm, x_mm, y_mm;
  };
  std::vector<Bump> lumps;
  // Grooves cut into the wall of any family: the radius grows by
  //   depth (1 + cos(2 pi u / width)) / 2 for |u| < width / 2,
  //   u = t - (z + tilt sin(theta - phase))
  // (t the ring's nominal height); rings are refined to 0.5 mm across each.
  struct Groove {
    double z_mm, width_mm, depth_mm, tilt_mm, phase_rad;
  };
  std::vector<Groove> grooves;
  // Width of the ground ring (0: drawn 40-80 mm from the seed, as always).
  double ground_width_mm = 0.0;
  // A container instead of ground (make_pit's `ground` must be false): a
  // flat lip this wide (radially, from the rim ring) in the rim plane and
  // an outer wall from the lip's outer edge container_wall_mm down (0: the
  // pit's depth + 10 mm), facing out. The lid of void_closed stays in the
  // rim plane, which is the lip's top plane.
  double container_lip_mm = 0.0;
  double container_wall_mm = 0.0;
};

// Parameters are drawn from the seed within the family's ranges.
Pit make_pit(Family f, bool ground, uint64_t seed, const PitOptions &opt = PitOptions());

// Exact volume of PitOptions' stone (the continuous bump, not its mesh).
double stone_volume_mm3(double height_mm, double radius_mm);

double signed_volume_mm3(const Mesh &m);

// The part of signed_volume_mm3(m) below the plane z = h_mm (the closed
// mesh clipped at the plane): the true void between the floor and a height,
// for comparing a measurement slab by slab (pitvol-sim slabs).
double volume_below_mm3(const Mesh &m, double h_mm);

}  // namespace pv::sim

#endif
