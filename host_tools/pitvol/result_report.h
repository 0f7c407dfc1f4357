// The measurement result as the host tools print it: JSON fields and the
// human summary. One place, so `pitvol measure` and `pitvol-usb-replay`
// report the same fields the same way.
#ifndef PV_TOOLS_RESULT_REPORT_H
#define PV_TOOLS_RESULT_REPORT_H

#include <cstdio>
#include <string>

#include "pitvol/json_writer.h"
#include "pitvol/pitvol.h"

namespace pv::tools {

// volume_cm3 and depth_mm (null unless measured: the caller decides, as a
// transport failure can void a result the core accepted), tilt, layers,
// points and the gap band.
void add_result_fields(JsonObject *o, const pv_result_t &r, bool measured);
// The wall coverage per height band, bottom first, as a JSON array.
std::string coverage_json(const pv_result_t &r);
// A PV_ERR_NOT_A_PIT's failed check in words with its figure and limit
// ("31.0 % of the points inside the void (a pit: at most 15.0 %)").
std::string check_figures(const pv_result_t &r);
// The lines "pit volume ... method ..." of a successful measurement.
void print_result_summary(std::FILE *f, const pv_result_t &r, pv_method_t method);
// "TOOL: no measurement (STATUS): message" and, where the result names
// them, the numbers behind the refusal (e.g. the wall gap's heights).
void print_refusal(std::FILE *f, const char *tool, pv_status_t st, const pv_result_t &r);

}  // namespace pv::tools

#endif
