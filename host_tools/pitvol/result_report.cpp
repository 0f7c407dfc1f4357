#include "pitvol/result_report.h"

#include <cstdio>
#include <string>

#include "pitvol/advice.h"

namespace pv::tools {

WarningLists warning_lists(const pv_result_t &r, const std::vector<std::string> &extra) {
  WarningLists w;
  w.warnings = extra;
  const uint32_t attention = pv_warnings_attention(r.warnings, r.unseen_share);
  for (uint32_t bit = 1; bit != 0 && bit <= PV_WARN_ALL; bit <<= 1) {
    if (!(r.warnings & bit) || pv_warning_message(bit) == nullptr) continue;
    (attention & bit ? w.warnings : w.notes).push_back(pv_warning_message(bit));
  }
  return w;
}

void add_result_fields(Json *o, const pv_result_t &r, bool measured,
                       const std::vector<std::string> &extra_warnings) {
  Json &j = *o;
  const Json none;  // null
  j["volume_cm3"] = measured ? Json(r.volume_cm3) : none;
  j["interval_cm3"] = measured ? Json(r.interval_cm3) : none;
  j["depth_mm"] = measured ? Json(r.depth_mm) : none;
  j["tilt_deg"] = r.tilt_deg;
  j["layers_used"] = r.layers_used;
  j["layers_rejected"] = r.layers_rejected;
  j["points_in"] = r.points_in;
  j["points_invalid"] = r.points_invalid;
  j["points_out_of_range"] = r.points_out_of_range;
  j["points_stored"] = r.points_stored;
  j["points_used"] = r.points_used;
  j["gap_from_mm"] = r.gap_from_mm;
  j["gap_to_mm"] = r.gap_to_mm;
  j["unseen_share"] = r.unseen_share;
  j["coverage"] = coverage_json(r);
  // Which plausibility check refused a PV_ERR_NOT_A_PIT, with its figures.
  if (r.failed_check != PV_PIT_CHECK_NONE) {
    j["failed_check"] = pv_pit_check_name(r.failed_check);
    j["check_value"] = r.check_value;
    j["check_limit"] = r.check_limit;
  }
  if (r.status != PV_OK) {
    pv_advice_t a;
    pv_advice_refusal(&r, r.status, &a);
    j["advice"] = a.sentence;
  }
  const WarningLists w = warning_lists(r, extra_warnings);
  j["warnings"] = w.warnings;
  j["notes"] = w.notes;
  j["warning_bits"] = r.warnings;
}

Json coverage_json(const pv_result_t &r) {
  Json a = Json::array();
  for (uint32_t b = 0; b < r.coverage_bands && b < PV_COVERAGE_BANDS; ++b) {
    a.push_back(json_decimals(double(r.coverage[b]), 3));
  }
  return a;
}

void print_result_summary(std::FILE *f, const pv_result_t &r, pv_method_t method,
                          const std::vector<std::string> &extra_warnings) {
  if (r.interval_cm3 > 0) {
    std::fprintf(f, "pit volume     %.1f +/- %.1f cm3\n", r.volume_cm3, r.interval_cm3);
  } else {
    std::fprintf(f, "pit volume     %.1f cm3\n", r.volume_cm3);
  }
  std::fprintf(f, "depth          %.1f mm\n", r.depth_mm);
  std::fprintf(f, "tilt           %.2f deg\n", r.tilt_deg);
  // The core's layers_used/rejected count wall bins for the surface model.
  if (method == PV_METHOD_SURFACE) {
    std::fprintf(f, "wall bins      %u seen, %u rejected\n", r.layers_used, r.layers_rejected);
    std::fprintf(f, "unseen wall    %.1f %% of the volume, bridged (in the interval)\n",
                 100.0 * r.unseen_share);
  } else {
    std::fprintf(f, "layers         %u used, %u rejected\n", r.layers_used, r.layers_rejected);
  }
  std::fprintf(f, "points         %llu read, %llu used%s\n", (unsigned long long)r.points_in,
               (unsigned long long)r.points_used,
               (r.warnings & PV_WARN_POINTS_THINNED) ? " (dense bins thinned to the fixed memory)" : "");
  std::fprintf(f, "method         %s (pitvol %s)\n", pv_method_name(method), PV_VERSION_STRING);
  for (const std::string &w : warning_lists(r, extra_warnings).warnings) {
    std::fprintf(f, "warning        %s\n", w.c_str());
  }
}

std::string check_figures(const pv_result_t &r) {
  char b[160];
  switch (r.failed_check) {
    case PV_PIT_CHECK_POINTS_INSIDE:
      std::snprintf(b, sizeof b, "%.1f %% of the points inside the void (a pit: at most %.1f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_NARROW_MOUTH:
      std::snprintf(b, sizeof b, "rim section / widest section %.2f (an open pit: at least %.2f)",
                    r.check_value, r.check_limit);
      break;
    case PV_PIT_CHECK_TOO_WIDE:
      std::snprintf(b, sizeof b, "wall radius up to %.0f mm (the grids reach %.0f mm)",
                    r.check_value, r.check_limit);
      break;
    case PV_PIT_CHECK_OPENING_TILT:
      std::snprintf(b, sizeof b, "opening tilted %.1f deg from the scanner's view (at most %.1f)",
                    r.check_value, r.check_limit);
      break;
    case PV_PIT_CHECK_SECTIONS:
      std::snprintf(b, sizeof b,
                    "volume %.3f x the largest section times the depth (a pit: above 0, at most %.2f)",
                    r.check_value, r.check_limit);
      break;
    case PV_PIT_CHECK_DOUBLED_WALL:
      std::snprintf(b, sizeof b,
                    "a second wall behind or within the first on two opposite sides: %.0f %% more of the wall than "
                    "across them (one scan: at most %.0f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_DOUBLED_SPARSE_WALL:
      std::snprintf(b, sizeof b,
                    "a second wall behind the first in %.0f %% of the wall's 10 deg sectors (one scan: at most "
                    "%.0f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_TOO_SMALL:
      std::snprintf(b, sizeof b,
                    "%.3g cm3 as millimetres (the smallest test hole: %.0f cm3); in cm it would be "
                    "%.4g cm3: --units cm",
                    r.check_value, r.check_limit, 1000 * r.check_value);
      break;
    case PV_PIT_CHECK_DOUBLED_FLOOR:
      std::snprintf(b, sizeof b,
                    "%.1f %% of the floor's points lie on a second floor above it (one scan: at most %.1f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_DOUBLED_RIM:
      std::snprintf(b, sizeof b,
                    "a second level of the surround under the rim with %.0f %% of the points of the first "
                    "(one scan: at most %.0f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_THIN_TOP:
      std::snprintf(b, sizeof b,
                    "the wall's top holds %.0f %% of the points per mm of the wall below it (one scan: at "
                    "least %.0f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_OVER_MOUTH:
      std::snprintf(b, sizeof b,
                    "%.1f %% of the points at the rim's height lie over the mouth (one scan: at most %.1f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    case PV_PIT_CHECK_SHIFTED_WALL:
      std::snprintf(b, sizeof b,
                    "%.0f %% of the wall's points lie behind it as one sideways shift puts them (one scan: at "
                    "most %.0f %%)",
                    100 * r.check_value, 100 * r.check_limit);
      break;
    default: std::snprintf(b, sizeof b, "no figure"); break;
  }
  return b;
}

void print_refusal(std::FILE *f, const char *tool, pv_status_t st, const pv_result_t &r) {
  pv_advice_t a;
  pv_advice_refusal(&r, st, &a);
  std::fprintf(f, "%s: no measurement (%s): %s\n", tool, pv_status_name(st), a.sentence);
  if (st == PV_ERR_NOT_A_PIT && r.failed_check != PV_PIT_CHECK_NONE) {
    std::fprintf(f, "%s: %s: measured %s\n", tool, pv_pit_check_name(r.failed_check),
                 check_figures(r).c_str());
  }
}

}  // namespace pv::tools
