// pitvol-monitor output (see report.h). JSON (nlohmann/json, as pitvol
// --json) and CSV print a number as the shortest decimal that reads back the
// same, so a value read back is the value the board sent.
#include "report.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "pitvol/advice.h"
#include "pitvol/density.h"
#include "pitvol/pitvol.h"
#include "pitvol/json.h"
#include "pitvol/result_report.h"

namespace pv::monitor {

namespace {

using pv::tools::Json;
using pv::tools::json_line;

std::string fmt(const char *f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The shortest decimal that reads back as the same double (11.8, not
// 11.800000000000001).
std::string g17(double v) {
  char b[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    if (std::strtod(b, nullptr) == v) break;
  }
  return b;
}

// 0: the board's clock was not set (no RTC, no network time): say so
// rather than print 1970.
std::string utc(uint64_t t) {
  if (t == 0) return "clock-not-set";
  const std::time_t tt = std::time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return b;
}

std::string status_name(int32_t code) {
  return pv_status_name(pv_status_t(code));
}

bool refused_by_check(const pitvol_Result &r) {
  return r.status == PV_ERR_NOT_A_PIT && r.failed_check != PV_PIT_CHECK_NONE;
}
bool wall_gap(const pitvol_Result &r) { return r.status == PV_ERR_WALL_GAP; }

// The fields of the core's result the board sent, for the shared rules
// (warnings, advice): no coverage or depth travels with a refusal.
pv_result_t core_result(const pitvol_Result &r) {
  pv_result_t pr{};
  pr.status = pv_status_t(r.status);
  pr.warnings = r.warnings;
  pr.unseen_share = r.unseen_share;
  pr.points_in = r.points_in;
  pr.points_used = r.points_used;
  pr.failed_check = r.failed_check;
  pr.check_value = r.check_value;
  pr.check_limit = r.check_limit;
  pr.gap_from_mm = r.gap_from_mm;
  pr.gap_to_mm = r.gap_to_mm;
  return pr;
}

// Why there is no volume, in the words pitvol measure uses (its
// check_figures(), on the fields the board sent), and what to do.
std::string refusal_text(const pitvol_Result &r) {
  std::string t;
  if (refused_by_check(r)) {
    t = std::string(" (") + pv_pit_check_name(r.failed_check) + ": " +
        pv::tools::check_figures(core_result(r)) + ")";
  } else if (wall_gap(r)) {
    t = " (no usable outline from " + fmt("%.1f", r.gap_from_mm) + " to " +
        fmt("%.1f", r.gap_to_mm) + " mm above the bottom)";
  }
  const pv_result_t pr = core_result(r);
  pv_advice_t a;
  pv_advice_refusal(&pr, pr.status, &a);
  return t + "\n         advice: " + a.sentence;
}

// "warnings: none" or the short forms of the bits that need attention,
// then a line per warning with its sentence and one line of notes
// (pitvol.h's table, as pitvol measure and the board print them).
std::string warnings_text(const pitvol_Result &r) {
  const uint32_t attention = pv_warnings_attention(r.warnings, r.unseen_share);
  std::string head, lines, notes;
  for (uint32_t bit = 1; bit <= PV_WARN_ALL; bit <<= 1) {
    if (!(r.warnings & bit) || pv_warning_short(bit) == nullptr) continue;
    if (attention & bit) {
      head += std::string(head.empty() ? "" : ", ") + pv_warning_short(bit);
      lines += std::string("\n         warning: ") + pv_warning_message(bit);
    } else {
      notes += std::string(notes.empty() ? "" : ", ") + pv_warning_short(bit);
    }
  }
  if (head.empty()) head = "none";
  return ", warnings: " + head + lines + (notes.empty() ? "" : "\n         notes: " + notes);
}

void warnings_json(Json &o, const pitvol_Result &r) {
  const uint32_t attention = pv_warnings_attention(r.warnings, r.unseen_share);
  std::vector<std::string> warnings, notes;
  for (uint32_t bit = 1; bit <= PV_WARN_ALL; bit <<= 1) {
    if (!(r.warnings & bit) || pv_warning_message(bit) == nullptr) continue;
    (attention & bit ? warnings : notes).push_back(pv_warning_message(bit));
  }
  o["warnings"] = warnings;
  o["notes"] = notes;
  o["warning_bits"] = r.warnings;
}

// Names of every set bit, space-separated, for a CSV cell.
std::string warning_names(uint32_t bits) {
  std::string t;
  for (uint32_t bit = 1; bit <= PV_WARN_ALL; bit <<= 1) {
    if ((bits & bit) && pv_warning_name(bit) != nullptr) t += std::string(t.empty() ? "" : " ") + pv_warning_name(bit);
  }
  return t;
}

void density_json(Json &o, const pitvol_Result &r) {
  const pitvol_Density &d = r.density;
  const bool open = d.flags & pitvol_DensityFlag_DENSITY_UNBOUNDED;
  o["density_flags"] = d.flags;
  if (d.flags & pitvol_DensityFlag_DENSITY_WET) {
    o["mass_g"] = d.mass_g;
    o["wet_kg_m3"] = d.wet_kg_m3;
    o["wet_low_kg_m3"] = d.wet_low_kg_m3;
    o["wet_high_kg_m3"] = open ? Json() : Json(d.wet_high_kg_m3);
  }
  if (d.flags & pitvol_DensityFlag_DENSITY_DRY) {
    o["moisture_percent"] = d.moisture_percent;
    o["dry_kg_m3"] = d.dry_kg_m3;
    o["dry_low_kg_m3"] = d.dry_low_kg_m3;
    o["dry_high_kg_m3"] = open ? Json() : Json(d.dry_high_kg_m3);
  }
  if (d.flags & pitvol_DensityFlag_DENSITY_COMPACTION) {
    o["reference_max_dry_kg_m3"] = d.reference_max_dry_kg_m3;
    o["compaction_percent"] = d.compaction_percent;
    o["compaction_low_percent"] = d.compaction_low_percent;
    o["compaction_high_percent"] = open ? Json() : Json(d.compaction_high_percent);
  }
}

const char *verdict_name(int v) { return pv_verdict_name(pv_verdict_t(v)); }

// A CSV cell: printable, and quoted when it holds a comma or a quote.
std::string csv_cell(const std::string &s) {
  const std::string p = printable(s);
  if (p.find_first_of(",\"") == std::string::npos) return p;
  std::string q = "\"";
  for (char c : p) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::string printable(const std::string &s) {
  std::string o;
  char b[8];
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      o += char(c);
      ++i;
      continue;
    }
    // A whole UTF-8 sequence (2 to 4 bytes, no overlong form) of a
    // printable character; C1 controls (U+0080..U+009F) are escaped.
    size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    if (n > 0 && i + n <= s.size()) {
      for (size_t k = 1; k < n; ++k)
        if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) n = 0;
    } else {
      n = 0;
    }
    if (n == 2 && c == 0xc2 && static_cast<unsigned char>(s[i + 1]) < 0xa0) {
      std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned char>(s[i + 1]));
      o += b;
      i += 2;
    } else if (n > 0) {
      o.append(s, i, n);
      i += n;
    } else {
      std::snprintf(b, sizeof b, "\\x%02x", c);
      o += b;
      ++i;
    }
  }
  return o;
}

const char *state_name(pitvol_DeviceState s) {
  switch (s) {
    case pitvol_DeviceState_STATE_IDLE: return "idle";
    case pitvol_DeviceState_STATE_SCANNING: return "scanning";
    case pitvol_DeviceState_STATE_COMPUTING: return "computing";
    case pitvol_DeviceState_STATE_RESULT: return "result";
    case pitvol_DeviceState_STATE_ERROR: return "error";
    default: return "unknown";
  }
}

std::string hello_text(const pitvol_Hello &h) {
  return "hello    pitvol " + printable(h.firmware_version) + ", device " + printable(h.device_id) +
         ", protocol " + std::to_string(h.protocol_version) + ", results " +
         std::to_string(h.first_result_id) + ".." + std::to_string(h.last_result_id);
}

std::string hello_json(const pitvol_Hello &h) {
  const Json o = {{"type", "hello"},
                  {"protocol_version", h.protocol_version},
                  {"firmware_version", std::string(h.firmware_version)},
                  {"device_id", std::string(h.device_id)},
                  {"capabilities", h.capabilities},
                  {"max_frame_bytes", h.max_frame_bytes},
                  {"first_result_id", h.first_result_id},
                  {"last_result_id", h.last_result_id}};
  return json_line(o);
}

std::string status_text(const pitvol_Status &s) {
  std::string t = std::string("status   ") + state_name(s.state) + ", " +
                  std::to_string(s.points) + " points";
  if (s.running_volume_cm3 > 0)
    t += ", volume " + fmt("%.1f", s.running_volume_cm3) + " +/- " + fmt("%.1f", s.running_interval_cm3) + " cm3";
  if (s.mass_set) t += ", mass " + fmt("%.1f", s.mass_g) + " g";
  if (s.moisture_set) t += ", moisture " + fmt("%.2f", s.moisture_percent) + " %";
  t += ", last result #" + std::to_string(s.last_result_id);
  return t;
}

std::string status_json(const pitvol_Status &s) {
  Json coverage = Json::array();
  for (pb_size_t i = 0; i < s.coverage_count; ++i)
    coverage.push_back(pv::tools::json_decimals(double(s.coverage[i]), 3));
  const Json o = {{"type", "status"},
                  {"state", state_name(s.state)},
                  {"points", s.points},
                  {"running_volume_cm3", s.running_volume_cm3},
                  {"running_interval_cm3", s.running_interval_cm3},
                  {"coverage", coverage},
                  {"last_result_id", s.last_result_id},
                  {"mass_g", s.mass_set ? Json(s.mass_g) : Json()},
                  {"moisture_percent", s.moisture_set ? Json(s.moisture_percent) : Json()},
                  {"frames_corrupt", s.frames_corrupt}};
  return json_line(o);
}

std::string result_text(const pitvol_Result &r) {
  std::string t = "result   #" + std::to_string(r.id) + " " + utc(r.time_unix_s) + " ";
  if (r.status != 0) return t + "no measurement: " + status_name(r.status) + refusal_text(r);
  t += printable(r.method);
  t += ", volume " + fmt("%.1f", r.volume_cm3) + " +/- " + fmt("%.1f", r.interval_cm3) +
       " cm3, depth " + fmt("%.1f", r.depth_mm) + " mm";
  t += warnings_text(r);
  const pitvol_Density &d = r.density;
  const bool open = d.flags & pitvol_DensityFlag_DENSITY_UNBOUNDED;
  auto range = [&](double v, double lo, double hi, const char *unit) {
    return fmt("%.0f", v) + " " + unit + " (" + fmt("%.0f", lo) + " .. " +
           (open ? std::string("?") : fmt("%.0f", hi)) + ")";
  };
  if (d.flags & pitvol_DensityFlag_DENSITY_WET)
    t += "\n         wet density " + range(d.wet_kg_m3, d.wet_low_kg_m3, d.wet_high_kg_m3, "kg/m3") +
         " from " + fmt("%.1f", d.mass_g) + " g";
  if (d.flags & pitvol_DensityFlag_DENSITY_DRY)
    t += "\n         dry density " + range(d.dry_kg_m3, d.dry_low_kg_m3, d.dry_high_kg_m3, "kg/m3") +
         " at " + fmt("%.2f", d.moisture_percent) + " % moisture";
  if (r.has_record && (r.record.test_id[0] || r.record.location[0] || r.record.operator_name[0]))
    t += "\n         test " + printable(r.record.test_id[0] ? r.record.test_id : "-") + ", " +
         printable(r.record.location[0] ? r.record.location : "-") + ", operator " +
         printable(r.record.operator_name[0] ? r.record.operator_name : "-");
  if (d.flags & pitvol_DensityFlag_DENSITY_COMPACTION)
    t += "\n         compaction " + fmt("%.1f", d.compaction_percent) + " % (" +
         fmt("%.1f", d.compaction_low_percent) + " .. " +
         (open ? std::string("?") : fmt("%.1f", d.compaction_high_percent)) + ") of " +
         fmt("%.0f", d.reference_max_dry_kg_m3) + " kg/m3";
  if (r.record.verdict != pitvol_Verdict_VERDICT_NONE) {
    t += "\n         verdict  " + std::string(verdict_name(r.record.verdict)) + " (required " +
         fmt("%.1f", r.record.required_compaction_percent) + " %)";
    if (r.record.verdict == pitvol_Verdict_VERDICT_UNDECIDED)
      t += ": the range straddles it; a volume interval under +/- " + fmt("%.1f", r.record.decides_within_cm3) +
           " cm3 would decide";
  }
  return t;
}

std::string result_json(const pitvol_Result &r) {
  const bool ok = r.status == 0;
  Json o = {{"type", "result"},
            {"id", r.id},
            {"time_unix_s", r.time_unix_s},
            {"time_utc", utc(r.time_unix_s)},
            {"status", status_name(r.status)},
            {"method", std::string(r.method)},
            {"volume_cm3", ok ? Json(r.volume_cm3) : Json()},
            {"interval_cm3", ok ? Json(r.interval_cm3) : Json()},
            {"depth_mm", ok ? Json(r.depth_mm) : Json()}};
  warnings_json(o, r);
  o["unseen_share"] = r.unseen_share;
  o["points_in"] = r.points_in;
  o["points_used"] = r.points_used;
  // As pitvol measure --json: the check that refused a PV_ERR_NOT_A_PIT with
  // its figures, the band of a PV_ERR_WALL_GAP.
  if (refused_by_check(r)) {
    o["failed_check"] = pv_pit_check_name(r.failed_check);
    o["check_value"] = r.check_value;
    o["check_limit"] = r.check_limit;
  }
  if (wall_gap(r)) {
    o["gap_from_mm"] = r.gap_from_mm;
    o["gap_to_mm"] = r.gap_to_mm;
  }
  if (!ok) {
    const pv_result_t pr = core_result(r);
    pv_advice_t a;
    pv_advice_refusal(&pr, pr.status, &a);
    o["advice"] = a.sentence;
  }
  density_json(o, r);
  const pitvol_Record &rec = r.record;
  o["test_id"] = std::string(rec.test_id);
  o["location"] = std::string(rec.location);
  o["operator"] = std::string(rec.operator_name);
  o["required_compaction_percent"] =
      rec.required_compaction_percent > 0 ? Json(rec.required_compaction_percent) : Json();
  o["verdict"] = rec.verdict != pitvol_Verdict_VERDICT_NONE ? Json(verdict_name(rec.verdict)) : Json();
  if (rec.verdict == pitvol_Verdict_VERDICT_UNDECIDED) o["decides_within_cm3"] = rec.decides_within_cm3;
  return json_line(o);
}

std::string error_text(const pitvol_Error &e) {
  return "error    " + printable(e.name) + ": " + printable(e.message);
}

std::string error_json(const pitvol_Error &e) {
  const Json o = {{"type", "error"}, {"code", e.code}, {"name", std::string(e.name)}, {"message", std::string(e.message)}};
  return json_line(o);
}

std::string result_csv_header() {
  return "id,time_unix_s,status,method,volume_cm3,interval_cm3,depth_mm,warnings,unseen_share,"
         "points_in,points_used,density_flags,mass_g,moisture_percent,wet_kg_m3,wet_low_kg_m3,"
         "wet_high_kg_m3,dry_kg_m3,dry_low_kg_m3,dry_high_kg_m3,reference_max_dry_kg_m3,"
         "compaction_percent,compaction_low_percent,compaction_high_percent,failed_check,"
         "check_value,check_limit,gap_from_mm,gap_to_mm,warning_names,test_id,location,operator,"
         "required_compaction_percent,verdict,decides_within_cm3";
}

std::string result_csv_row(const pitvol_Result &r) {
  const pitvol_Density &d = r.density;
  const bool ok = r.status == 0;
  const bool wet = d.flags & pitvol_DensityFlag_DENSITY_WET;
  const bool dry = d.flags & pitvol_DensityFlag_DENSITY_DRY;
  const bool rc = d.flags & pitvol_DensityFlag_DENSITY_COMPACTION;
  const bool open = d.flags & pitvol_DensityFlag_DENSITY_UNBOUNDED;
  auto num = [](bool valid, double v) { return valid ? g17(v) : std::string(); };
  std::string row = std::to_string(r.id) + "," + std::to_string(r.time_unix_s) + "," +
                    status_name(r.status) + "," + csv_cell(r.method) + "," + num(ok, r.volume_cm3) + "," +
                    num(ok, r.interval_cm3) + "," + num(ok, r.depth_mm) + "," +
                    std::to_string(r.warnings) + "," + g17(r.unseen_share) + "," +
                    std::to_string(r.points_in) + "," + std::to_string(r.points_used) + "," +
                    std::to_string(d.flags) + ",";
  row += num(wet, d.mass_g) + "," + num(dry, d.moisture_percent) + "," + num(wet, d.wet_kg_m3) + "," +
         num(wet, d.wet_low_kg_m3) + "," + num(wet && !open, d.wet_high_kg_m3) + "," +
         num(dry, d.dry_kg_m3) + "," + num(dry, d.dry_low_kg_m3) + "," + num(dry && !open, d.dry_high_kg_m3) +
         "," + num(rc, d.reference_max_dry_kg_m3) + "," + num(rc, d.compaction_percent) + "," +
         num(rc, d.compaction_low_percent) + "," + num(rc && !open, d.compaction_high_percent);
  // The refusal's detail (empty where it does not apply), as in the JSON.
  const bool by_check = refused_by_check(r), gap = wall_gap(r);
  row += std::string(",") + (by_check ? pv_pit_check_name(r.failed_check) : "") + "," +
         num(by_check, r.check_value) + "," + num(by_check, r.check_limit) + "," +
         num(gap, r.gap_from_mm) + "," + num(gap, r.gap_to_mm) + "," + warning_names(r.warnings);
  const pitvol_Record &rec = r.record;
  row += "," + csv_cell(rec.test_id) + "," + csv_cell(rec.location) + "," + csv_cell(rec.operator_name) + "," +
         num(rec.required_compaction_percent > 0, rec.required_compaction_percent) + "," +
         (rec.verdict ? verdict_name(rec.verdict) : "") + "," +
         num(rec.verdict == pitvol_Verdict_VERDICT_UNDECIDED, rec.decides_within_cm3);
  return row;
}

}  // namespace pv::monitor
