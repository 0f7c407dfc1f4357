// The measurement result as the host tools print it: JSON fields and the
// human summary. One place, so `pitvol measure` and `pitvol-usb-replay`
// report the same fields the same way.
#ifndef PV_TOOLS_RESULT_REPORT_H
#define PV_TOOLS_RESULT_REPORT_H

#include <cstdio>
#include <string>
#include <vector>

#include "pitvol/json.h"
#include "pitvol/pitvol.h"

namespace pv::tools {

// The result's warning bits in words, from the core's table (pitvol.h):
// those that need the user's attention (extra ones first, e.g. a units
// warning of the tool) and the notes (set bits that do not).
struct WarningLists {
  std::vector<std::string> warnings, notes;
};
WarningLists warning_lists(const pv_result_t &r, const std::vector<std::string> &extra = {});

// volume_cm3 and depth_mm (null unless measured: the caller decides, as a
// transport failure can void a result the core accepted), tilt, layers,
// points, the gap band, the warnings (with extra ones first), notes and
// warning_bits, and for a refusal the advice.
void add_result_fields(Json *o, const pv_result_t &r, bool measured,
                       const std::vector<std::string> &extra_warnings = {});
// The wall coverage per height band, bottom first, to 3 decimals.
Json coverage_json(const pv_result_t &r);
// A PV_ERR_NOT_A_PIT's failed check in words with its figure and limit
// ("31.0 % of the points inside the void (a pit: at most 15.0 %)").
std::string check_figures(const pv_result_t &r);
// The lines "pit volume ... method ..." of a successful measurement, the
// counts labelled per method (wall bins for surface, layers for paper and
// polar), then one "warning" line per warning.
void print_result_summary(std::FILE *f, const pv_result_t &r, pv_method_t method,
                          const std::vector<std::string> &extra_warnings = {});
// "TOOL: no measurement (STATUS): what went wrong and what to do" from the
// failing check (pitvol/advice.h: too few points, the unseen band and
// where to aim, ...) and, where the result names them, the numbers behind
// the refusal (the failed check's figure and limit).
void print_refusal(std::FILE *f, const char *tool, pv_status_t st, const pv_result_t &r);

}  // namespace pv::tools

#endif
