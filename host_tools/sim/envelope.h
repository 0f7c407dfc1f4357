// The operating envelope as a test set: random scans drawn over wide
// ranges of pit size, shape, surround and scanning condition, each with its
// exact volume (docs/accuracy.md, "The envelope sweeps").
//
// A sweep is (seed, count): case i draws everything from splitmix64
// streams of (seed, i), one stream per choice, so a case is the same
// whatever the count, and forcing the family or the condition (the sweep's
// filters) leaves every other draw of the case as it was. Seeds 1-999 are
// tuning seeds (rules and thresholds may be chosen on them); seeds 1000
// and up are fresh (measured only, after the rules are fixed).
//
// Per case:
// - family: the 12 of pit_geometry.h (a condition that needs a flat floor
//   draws among the 10 that have one);
// - size: a size class (<3 L, 3-30 L, 30-150 L, 150-600 L; a quarter
//   each), the volume log-uniform in it from 0.8 L, the family's own
//   depth-to-diameter ratio times 0.35-1.4 (at most 3), radius within
//   50-750 mm and depth within 80-800 mm (PitOptions::scale_xy, scale_z);
// - surround: ground ring (1/2; 40-80 mm wide, wider round big pits),
//   none (1/4), a container with a 3-15 mm lip and its outer wall (1/4);
// - scan: noise 0.02-0.2 mm, tilt 0-25 deg, points from the pit's area;
// - one condition (envelope_conditions()): what departs from a plain scan.
#ifndef PV_SIM_ENVELOPE_H
#define PV_SIM_ENVELOPE_H

#include <cstdint>
#include <string>
#include <vector>

#include "sim/handheld_scan.h"
#include "sim/pit_geometry.h"
#include "sim/scan_writer.h"

namespace pv::sim {

// The sweep seeds no rule may be tuned on start here.
constexpr uint64_t kFirstFreshSeed = 1000;

// Forces the family or the condition of every case ("" leaves it drawn).
struct SweepFilter {
  std::string family, condition;
};

struct EnvelopeCase {
  std::string name;  // s<seed>-<index>-<family>-<g|n|c>-<condition>[-1x]
  uint64_t sweep_seed = 0;
  uint32_t index = 0;
  Family family = Family::Cylinder;
  uint64_t pit_seed = 0;
  bool ground = true;
  std::string surround;   // "ground", "none", "container"
  PitOptions pit;
  std::string condition;  // one of envelope_conditions()
  double target_radius_mm = 0, target_depth_mm = 0;  // drawn size (the pit's own: its JSON)
  ScanParams scan;            // pass 0 (the 1x twin's whole scan)
  uint32_t passes = 1;        // long scans: 2-30; a slip: 2
  uint32_t pass_points = 0;   // points per pass after the first
  double jitter_mm = 0;       // registration jitter of the later passes
  uint32_t copies = 1;        // exact duplicates
  bool interleave = false;
  double slip_mm[3] = {0, 0, 0};  // second pass's offset, pit frame
  std::string units = "mm";   // of the PLY
  std::string twin;           // the 1x twin's name (long, duplicates, slips)
  bool is_twin = false;
  std::string twin_of;        // the twin's long scan
  // What a correct instrument does with it: "measure" (a refusal is
  // false), "refuse_or_hold" (refused, or the interval holds the truth:
  // slips), "refuse_or_right" (units: refused, or measured right), or
  // "gap_ok" (a WALL_GAP refusal is right: the scan left over a tenth of
  // the wall unseen; set after the scan).
  std::string expect = "measure";
};

const std::vector<std::string> &envelope_conditions();

// Case `index` of sweep `seed`; false with *error when a filter names no
// family or condition.
bool draw_envelope_case(uint64_t seed, uint32_t index, const SweepFilter &filter,
                        EnvelopeCase *out, std::string *error);

// The same pit scanned once: pass 0 alone, no copies, no slip, millimetres.
EnvelopeCase envelope_twin(const EnvelopeCase &c);

// The passes, motions, copies and unit of the case's scan.
ScanPlan envelope_plan(const EnvelopeCase &c, const Pit &pit);

// "<3 L", "3-30 L", "30-150 L", ">150 L".
const char *size_class(double volume_cm3);

// The case's manifest object (one line of JSON) and CSV row; the header
// names the CSV's columns (its first ten as pitvol-sim corpus writes them).
std::string envelope_json(const EnvelopeCase &c, const Pit &pit, const WrittenPlan &w);
std::string envelope_csv_header();
std::string envelope_csv_row(const EnvelopeCase &c, const Pit &pit, const WrittenPlan &w);

}  // namespace pv::sim

#endif
