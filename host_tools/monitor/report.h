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

// A string the board sent, safe to print on a terminal: control
// characters (C0, DEL, C1) and bytes that are not UTF-8 become \xNN or
// \u00NN escapes, so a device cannot move the cursor, clear the screen or
// retitle the window. Printable UTF-8 (°, ³, ±) stays as it is.
std::string printable(const std::string &s);

}  // namespace pv::monitor

#endif
