// pitvol-accuracy DIR --envelope: the envelope table of a sweep made by
// `pitvol-sim sweep` (docs/accuracy.md, "The envelope sweeps").
#ifndef PV_TOOLS_ENVELOPE_TABLE_H
#define PV_TOOLS_ENVELOPE_TABLE_H

#include <cstddef>
#include <string>
#include <vector>

#include "peer_runner.h"

namespace pv::tools {

// pitvol-accuracy SWEEP_DIR --envelope's options (parsed in
// pitvol_accuracy.cpp).
struct EnvelopeOptions {
  std::string dir;  // the sweep
  std::string method = "surface", title, config;
  bool markdown = false;
  int jobs = 1;
  size_t worst_n = 30;
  std::vector<std::string> peers;
  PeerOptions popt;
};

// Returns the exit status.
int envelope_main(const EnvelopeOptions &opt);

}  // namespace pv::tools

#endif
