// The peers of the accuracy report (docs/accuracy.md "Peers"): other
// programs' volumes of the same scans, for pitvol-accuracy to print beside
// pitvol's methods.
//
//   grid25        the reference 2.5D grid (host_tools/peers/grid25.h), 1 mm
//   cloudcompare  CloudCompare's 2.5D volume, run headless on the levelled
//                 cloud (-VOLUME -GRID_STEP 2 -CONST_HEIGHT rim), where the
//                 `CloudCompare` program is installed (install-deps.sh --peers)
//   poisson       screened Poisson (Open3D, depth 9) clipped at the rim plane
//                 (host_tools/peers/poisson/poisson_volume.py, in a venv that
//                 setup-venv.sh makes once under the build directory)
//
// Every peer measures the cloud that `pitvol measure --export-levelled`
// writes: pitvol's own levelling and rim, so the peers and pitvol differ
// only in how they turn a levelled cloud into a volume. The slow peers'
// results are cached per case (CACHE/<case>.json), keyed by that levelling:
// a changed levelling or rim recomputes them.
#ifndef PV_TOOLS_PEER_RUNNER_H
#define PV_TOOLS_PEER_RUNNER_H

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace pv::tools {

// Values of a flat JSON object as `pitvol measure --json` and the peers
// print it ("key": value): a string (escapes undone), or a number (NAN
// when absent or null).
std::string json_str(const std::string &j, const std::string &key);
double json_num(const std::string &j, const std::string &key);

// stdout of a shell command, and its exit status (pclose's).
std::string capture(const std::string &cmd, int *status);

// The folder of the running program (where pitvol and the peers are).
std::string self_dir();

// What the accuracy tools read of `pitvol measure FILE --json --no-progress
// --method METHOD [--config CONFIG]`, pitvol from bin_dir.
struct Measured {
  std::string status;  // PV_OK, the failure's name, or NO_OUTPUT
  std::string failed_check, message;
  double volume_cm3 = NAN, interval_cm3 = NAN, check_value = NAN;
  double points_in = NAN, points_used = NAN, total_ms = NAN;
};
Measured measure(const std::string &bin_dir, const std::string &file, const std::string &method,
                 const std::string &config = "");

struct PeerResult {
  std::string status;  // "ok", else why there is no volume
  double volume_cm3 = NAN;
  double ms = NAN;     // the peer's own time for the scan (not the export)
};

struct PeerOptions {
  std::string bin_dir;         // where pitvol and the peers' scripts live
  std::string cache_dir;
  std::string export_method;   // pitvol method whose levelling the peers use
  bool cached_only = false;    // do not compute what the cache lacks
  double grid_mm = 1.0;        // grid25 cell
  double cc_grid_mm = 2.0;     // CloudCompare grid step
};

class PeerRunner {
 public:
  explicit PeerRunner(PeerOptions opt) : opt_(std::move(opt)) {}
  // Results of the named peers for one scan, computing what is not cached.
  std::map<std::string, PeerResult> run(const std::string &case_name, const std::string &scan,
                                        const std::vector<std::string> &peers);
  static bool known(const std::string &peer);

 private:
  PeerResult grid25(const std::string &ply);
  PeerResult cloudcompare(const std::string &dir, const std::string &ply, double rim_mm);
  PeerResult poisson(const std::string &ply);
  std::string python();  // the venv's python, or "" (reason in python_error_)

  PeerOptions opt_;
  bool python_tried_ = false;
  std::string python_, python_error_;
};

}  // namespace pv::tools

#endif
