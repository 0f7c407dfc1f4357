// `pitvol measure`: stream a scan file through a core session.
#ifndef PV_TOOLS_MEASURE_H
#define PV_TOOLS_MEASURE_H

#include <string>

#include "pitvol/pitvol.h"
#include "scanio/scan_reader.h"

namespace pv::tools {

struct MeasureOptions {
  std::string path;
  scanio::Format format = scanio::Format::Auto;
  double scale_to_mm = 1.0;  // --units
  std::string units = "mm";
  bool json = false;
  bool progress = true;      // only shown when stderr is a terminal
  std::string layers_csv;    // --layers FILE: per-layer detail, if not empty
  std::string export_levelled;  // --export-levelled FILE: levelled PLY, if not empty
  std::string export_dir;    // --export DIR: files for a report, if not empty
  pv_config_t cfg{};
};

// Exit codes (README): 0 measured, 2 usage, 3 unreadable or invalid input,
// 4 the scan cannot support a measurement, 5 internal error.
enum Exit { kExitOk = 0, kExitUsage = 2, kExitInput = 3, kExitNoMeasurement = 4, kExitInternal = 5 };

int run_measure(const MeasureOptions &opt);

}  // namespace pv::tools

#endif
