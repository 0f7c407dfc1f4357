// The regression corpus: which pits, poses and noise levels, by seed.
// Generated at test time (nothing large is committed); the tracked file
// tests/corpus/expected.csv holds each case's measured result.
#ifndef PV_SIM_CORPUS_H
#define PV_SIM_CORPUS_H

#include <string>
#include <vector>

#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"

namespace pv::sim {

struct CorpusCase {
  std::string name;  // "<family>-<g|n>-<seed>", also the file stem
  Family family;
  bool ground;
  uint64_t seed;
  ScanParams scan;
};

// Three cases per family: with ground, without, and a third seed with
// another noise level: 33 cases over 11 families.
std::vector<CorpusCase> standard_corpus();

}  // namespace pv::sim

#endif
