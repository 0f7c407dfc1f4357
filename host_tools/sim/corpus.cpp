#include "sim/corpus.h"

namespace pv::sim {

std::vector<CorpusCase> standard_corpus() {
  // Range noise from the 0.02 .. 0.2 mm, cycled over the cases.
  const double noise_mm[] = {0.02, 0.05, 0.1, 0.2};
  std::vector<CorpusCase> cases;
  for (int f = 0; f < int(Family::kCount); ++f) {
    for (int k = 0; k < 3; ++k) {
      CorpusCase c;
      c.family = Family(f);
      c.seed = uint64_t(k + 1);
      c.ground = k == 0 || (k == 2 && f % 2 == 0);
      c.scan.seed = 1000 * uint64_t(f) + c.seed;
      c.scan.noise_mm = noise_mm[(f + k) % 4];
      c.name = std::string(family_name(c.family)) + (c.ground ? "-g-" : "-n-") +
               std::to_string(c.seed);
      cases.push_back(c);
    }
  }
  return cases;
}

}  // namespace pv::sim
