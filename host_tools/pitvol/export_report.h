// `pitvol measure FILE --export DIR`: what a report needs to show a
// measurement (host_tools/report, docs/report.md has the file formats):
//   result.json   the --json object
//   model.json    transform, rim, wall grid geometry, export counts
//   points.csv    levelled points, every k-th (at most kMaxExportPoints)
//   layers.csv    area against height per 0.5 mm layer, kept/bridged flags
//   coverage.csv  share of the wall seen per height band
//   wall_grid.csv the surface model's wall radius R(theta, z) and state
//   outline.csv   R(theta) at a few heights (from the wall grid)
// The last two only for method surface (the per-layer methods have no
// wall grid).
#ifndef PV_TOOLS_EXPORT_REPORT_H
#define PV_TOOLS_EXPORT_REPORT_H

#include <cstdint>
#include <cstdio>
#include <string>

#include "measure.h"
#include "pitvol/pitvol.h"

namespace pv::tools {

// Bounded, so that a report stays small and quick whatever the scan.
constexpr uint64_t kMaxExportPoints = 50000;

// Makes DIR (one level) if missing; false with *err if it cannot.
bool prepare_export_dir(const std::string &dir, std::string *err);

// Writes the files above. count: exportable points in the file (the
// decimation stride is ceil(count / kMaxExportPoints): deterministic).
// result_json: the --json object. false with *err on the first failure.
bool export_report(const MeasureOptions &opt, pv_session_t *session, const pv_result_t &r,
                   uint64_t count, const std::string &result_json, std::string *err);

// Area against height, one row per 0.5 mm layer (layers.csv of the export
// and `--layers FILE`): for method surface z_mm,area_mm2,kept,unseen_share,
// bridged; for paper and polar z_mm,area_mm2,points,kept,shape,bridged.
// wall_grid: the export's wall grid, or nullptr for the per-layer methods.
void write_layers_rows(FILE *f, const pv_session_t *s, const void *wall_grid);
// The same rows for `--layers`, reading the wall grid itself.
bool write_layers_file(const MeasureOptions &opt, pv_session_t *s, FILE *f);

}  // namespace pv::tools

#endif
