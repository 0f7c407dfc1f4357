// The corpora: which pits, poses and noise levels, by seed. Generated at
// test time (nothing large is committed); the tracked file
// tests/corpus/expected.csv holds each standard case's measured result.
//
// Three sets (docs/accuracy.md, "The three corpus sets"):
// - standard: the regression corpus every tuning is measured on;
// - holdout: the same 11 families and mix of ground/noise, other pit and
//   scan seeds, that no tuning looks at;
// - stress: cases that break the standard assumptions (one side unscanned,
//   30k and 2M points, tilted ground, dropout patches, a stone on the floor,
//   a pit at the depth capacity), each with its exact volume.
#ifndef PV_SIM_CORPUS_H
#define PV_SIM_CORPUS_H

#include <string>
#include <vector>

#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"

namespace pv::sim {

struct CorpusCase {
  std::string name;  // "<family>-<g|n>-<seed>" (stress: "<stress>-" first), the file stem
  Family family;
  bool ground;
  uint64_t seed;
  ScanParams scan;
  PitOptions pit;      // defaults outside the stress set
  std::string set;     // "standard", "holdout" or "stress"
  std::string stress;  // what the case stresses; "none" outside the stress set
};

// Three cases per family: with ground, without, and a third seed with
// another noise level: 33 cases over 11 families.
std::vector<CorpusCase> standard_corpus();

// The same families and composition, pit seeds 101-103 and scan seeds of
// their own; the ground pattern of the third case is the standard one's
// complement. 33 cases.
std::vector<CorpusCase> holdout_corpus();

// One case (or two) per broken assumption; see corpus.cpp.
std::vector<CorpusCase> stress_corpus();

// By set name ("standard", "holdout", "stress"); false if unknown.
bool corpus_by_name(const std::string &set, std::vector<CorpusCase> *out);

}  // namespace pv::sim

#endif
