// How pitvol-monitor prints what the board sends: human lines, JSON lines
// (one object per message) and CSV rows for a fetched log.
#ifndef PV_MONITOR_REPORT_H
#define PV_MONITOR_REPORT_H

#include <string>

#include "pitvol/link.h"

namespace pv::monitor {

std::string hello_text(const pitvol_Hello &h);
std::string hello_json(const pitvol_Hello &h);
std::string status_text(const pitvol_Status &s);
std::string status_json(const pitvol_Status &s);
std::string result_text(const pitvol_Result &r);
std::string result_json(const pitvol_Result &r);
std::string error_text(const pitvol_Error &e);
std::string error_json(const pitvol_Error &e);

// CSV: the header line and one row per result, same columns.
std::string result_csv_header();
std::string result_csv_row(const pitvol_Result &r);

const char *state_name(pitvol_DeviceState s);

}  // namespace pv::monitor

#endif
