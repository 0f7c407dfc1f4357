#include "pitvol/result_report.h"

#include <cstdio>
#include <string>

namespace pv::tools {

void add_result_fields(JsonObject *o, const pv_result_t &r, bool measured) {
  if (measured) {
    o->num("volume_cm3", r.volume_cm3)
        .num("interval_cm3", r.interval_cm3)
        .num("depth_mm", r.depth_mm);
  } else {
    o->null("volume_cm3").null("interval_cm3").null("depth_mm");
  }
  o->num("tilt_deg", r.tilt_deg)
      .integer("layers_used", r.layers_used)
      .integer("layers_rejected", r.layers_rejected)
      .integer("points_in", r.points_in)
      .integer("points_invalid", r.points_invalid)
      .integer("points_out_of_range", r.points_out_of_range)
      .integer("points_stored", r.points_stored)
      .integer("points_used", r.points_used)
      .num("gap_from_mm", r.gap_from_mm)
      .num("gap_to_mm", r.gap_to_mm)
      .num("unseen_share", r.unseen_share)
      .raw("coverage", coverage_json(r));
}

std::string coverage_json(const pv_result_t &r) {
  std::string a = "[";
  for (uint32_t b = 0; b < r.coverage_bands && b < PV_COVERAGE_BANDS; ++b) {
    char v[32];
    std::snprintf(v, sizeof v, "%s%.3f", b ? "," : "", double(r.coverage[b]));
    a += v;
  }
  return a + "]";
}

void print_result_summary(std::FILE *f, const pv_result_t &r, pv_method_t method) {
  if (r.interval_cm3 > 0) {
    std::fprintf(f, "pit volume     %.1f +/- %.1f cm3\n", r.volume_cm3, r.interval_cm3);
  } else {
    std::fprintf(f, "pit volume     %.1f cm3\n", r.volume_cm3);
  }
  std::fprintf(f, "depth          %.1f mm\n", r.depth_mm);
  std::fprintf(f, "tilt           %.2f deg\n", r.tilt_deg);
  std::fprintf(f, "layers         %u used, %u rejected\n", r.layers_used, r.layers_rejected);
  std::fprintf(f, "points         %llu in, %llu used\n", (unsigned long long)r.points_in,
               (unsigned long long)r.points_used);
  std::fprintf(f, "method         %s (pitvol %s)\n", pv_method_name(method), PV_VERSION_STRING);
}

void print_refusal(std::FILE *f, const char *tool, pv_status_t st, const pv_result_t &r) {
  std::fprintf(f, "%s: no measurement (%s): %s\n", tool, pv_status_name(st), pv_status_message(st));
  if (st == PV_ERR_WALL_GAP) {
    std::fprintf(f, "%s: the wall from %.1f mm to %.1f mm above the bottom has no usable outline\n",
                 tool, r.gap_from_mm, r.gap_to_mm);
  }
}

}  // namespace pv::tools
