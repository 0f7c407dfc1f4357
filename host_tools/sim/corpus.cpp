#include "sim/corpus.h"

namespace pv::sim {

namespace {

std::string case_name(Family f, bool ground, uint64_t seed) {
  return std::string(family_name(f)) + (ground ? "-g-" : "-n-") + std::to_string(seed);
}

}  // namespace

std::vector<CorpusCase> standard_corpus() {
  // Range noise from the 0.02 .. 0.2 mm, cycled over the cases.
  const double noise_mm[] = {0.02, 0.05, 0.1, 0.2};
  std::vector<CorpusCase> cases;
  for (int f = 0; f < kCorpusFamilies; ++f) {
    for (int k = 0; k < 3; ++k) {
      CorpusCase c;
      c.family = Family(f);
      c.seed = uint64_t(k + 1);
      c.ground = k == 0 || (k == 2 && f % 2 == 0);
      c.scan.seed = 1000 * uint64_t(f) + c.seed;
      c.scan.noise_mm = noise_mm[(f + k) % 4];
      c.name = case_name(c.family, c.ground, c.seed);
      c.set = "standard";
      c.stress = "none";
      cases.push_back(c);
    }
  }
  return cases;
}

std::vector<CorpusCase> holdout_corpus() {
  // Same composition as the standard set; disjoint pit seeds (101-103 against
  // 1-3) and scan seeds (500000 + ... against at most 10003), the noise
  // cycle shifted by two, and the third case's ground the complement of the
  // standard one's.
  const double noise_mm[] = {0.02, 0.05, 0.1, 0.2};
  std::vector<CorpusCase> cases;
  for (int f = 0; f < kCorpusFamilies; ++f) {
    for (int k = 0; k < 3; ++k) {
      CorpusCase c;
      c.family = Family(f);
      c.seed = uint64_t(101 + k);
      c.ground = k == 0 || (k == 2 && f % 2 == 1);
      c.scan.seed = 500000 + 1000 * uint64_t(f) + c.seed;
      c.scan.noise_mm = noise_mm[(f + k + 2) % 4];
      c.name = case_name(c.family, c.ground, c.seed);
      c.set = "holdout";
      c.stress = "none";
      cases.push_back(c);
    }
  }
  return cases;
}

std::vector<CorpusCase> stress_corpus() {
  std::vector<CorpusCase> cases;
  uint64_t seed = 201;  // pit seeds 201.., scan seeds 700000 + pit seed
  auto add = [&](const char *stress, Family f, bool ground, double noise_mm) -> CorpusCase & {
    CorpusCase c;
    c.family = f;
    c.ground = ground;
    c.seed = seed++;
    c.scan.seed = 700000 + c.seed;
    c.scan.noise_mm = noise_mm;
    c.name = std::string(stress) + "-" + case_name(f, ground, c.seed);
    c.set = "stress";
    c.stress = stress;
    cases.push_back(c);
    return cases.back();
  };
  // One side missing: the operator walks 90 or 120 deg of the way round
  // (90 deg leaves about a 60 deg sector of wall with under 5 % of the
  // points of the best-seen sector, 120 deg a thinner one; see
  // test_corpus_sets).
  add("one_side", Family::Cylinder, true, 0.05).scan.path_arc_deg = 90.0;
  add("one_side", Family::HandDug, false, 0.05).scan.path_arc_deg = 120.0;
  // Point counts far from the standard 300k.
  add("sparse", Family::HandDug, true, 0.05).scan.target_points = 30000;
  add("sparse", Family::Elliptical, false, 0.1).scan.target_points = 30000;
  add("dense", Family::Cylinder, true, 0.05).scan.target_points = 2000000;
  // The ground a few degrees off the floor plane; the lid is the ground.
  {
    CorpusCase &c = add("tilted_ground", Family::Cylinder, true, 0.05);
    c.pit.ground_tilt_deg = 4.0;
    c.pit.ground_tilt_azimuth_rad = 1.0;
  }
  {
    CorpusCase &c = add("tilted_ground", Family::Tapered, true, 0.1);
    c.pit.ground_tilt_deg = 2.5;
    c.pit.ground_tilt_azimuth_rad = 4.0;
  }
  // Wet or dark soil: balls of 20-40 mm on the wall and floor return nothing.
  add("dropout", Family::Cylinder, true, 0.05).scan.dropout_patches = 8;
  add("dropout", Family::Tapered, false, 0.05).scan.dropout_patches = 6;
  // A stone 40 mm high, 70 mm across, off the axis; the void excludes it.
  {
    CorpusCase &c = add("stone", Family::Cylinder, true, 0.05);
    c.pit.stone_height_mm = 40.0;
    c.pit.stone_radius_mm = 35.0;
    c.pit.stone_x_mm = 35.0;
    c.pit.stone_y_mm = -20.0;
  }
  // 600 mm deep: within the core's depth range (max_layers 1920 x 0.5 mm = 960 mm).
  add("depth_capacity", Family::Cylinder, true, 0.05).pit.depth_mm = 600.0;
  return cases;
}

bool corpus_by_name(const std::string &set, std::vector<CorpusCase> *out) {
  if (set == "standard") *out = standard_corpus();
  else if (set == "holdout") *out = holdout_corpus();
  else if (set == "stress") *out = stress_corpus();
  else return false;
  return true;
}

}  // namespace pv::sim
