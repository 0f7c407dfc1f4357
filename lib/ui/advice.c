/* What a scan without a volume tells the technician (pitvol/advice.h). */
#include "pitvol/advice.h"

#include <stdio.h>
#include <string.h>

/* The widest run of coverage bands under `share`, as heights above the
 * floor; 0 if there is none. */
static int widest_run(const pv_result_t *r, float share, double *lo, double *hi) {
  const uint32_t n = r->coverage_bands <= PV_COVERAGE_BANDS ? r->coverage_bands : 0;
  if (n == 0 || !(r->depth_mm > 0)) return 0;
  uint32_t best_from = 0, best_len = 0;
  for (uint32_t b = 0; b < n;) {
    if (r->coverage[b] >= share) {
      ++b;
      continue;
    }
    uint32_t e = b;
    while (e < n && r->coverage[e] < share) ++e;
    if (e - b > best_len) {
      best_from = b;
      best_len = e - b;
    }
    b = e;
  }
  if (best_len == 0) return 0;
  *lo = r->depth_mm * best_from / n;
  *hi = r->depth_mm * (best_from + best_len) / n;
  return 1;
}

/* The lower wall hides under the rim: look down into the pit. The upper
 * wall is missed when the scanner stays low. */
static int lower_half(const pv_result_t *r, double lo, double hi) {
  const double depth = r->depth_mm > 0 ? r->depth_mm : (r->gap_to_mm > 0 ? r->gap_to_mm : 0);
  return depth <= 0 || (lo + hi) / 2 < depth / 2;
}

void pv_advice_grouped(uint64_t v, char *out, size_t cap) {
  char raw[32];
  snprintf(raw, sizeof raw, "%llu", (unsigned long long)v);
  const size_t n = strlen(raw);
  size_t o = 0;
  for (size_t i = 0; i < n && o + 2 < cap; ++i) {
    if (i > 0 && (n - i) % 3 == 0) out[o++] = ' ';
    out[o++] = raw[i];
  }
  out[o] = '\0';
}

int pv_advice_too_few_points(const pv_result_t *r, pv_status_t st) {
  if (st == PV_ERR_TOO_FEW_POINTS) return 1;
  if (st != PV_ERR_WALL_GAP && st != PV_ERR_TOO_FEW_LAYERS && st != PV_ERR_NO_RIM) return 0;
  if (r->points_in < PV_ADVICE_FEW_POINTS) return 1;
  const double depth = r->depth_mm > 0 ? r->depth_mm : r->gap_to_mm;
  if (st == PV_ERR_WALL_GAP && depth > 0 && r->gap_to_mm - r->gap_from_mm >= 0.8 * depth) return 1;
  const uint32_t n = r->coverage_bands <= PV_COVERAGE_BANDS ? r->coverage_bands : 0;
  uint32_t thin = 0;
  for (uint32_t b = 0; b < n; ++b) thin += r->coverage[b] < PV_ADVICE_SEEN_SHARE;
  return n > 0 && 4 * thin >= 3 * n;
}

int pv_advice_live(const pv_result_t *r, pv_status_t st, char *line1, size_t cap1, char *line2,
                   size_t cap2) {
  line1[0] = line2[0] = '\0';
  double lo = 0, hi = 0;
  const char *what = "not seen";
  if (st == PV_ERR_WALL_GAP && r->gap_to_mm > r->gap_from_mm) {
    lo = r->gap_from_mm;
    hi = r->gap_to_mm;
  } else if (widest_run(r, PV_ADVICE_UNSEEN_SHARE, &lo, &hi)) {
  } else if (widest_run(r, PV_ADVICE_SEEN_SHARE, &lo, &hi)) {
    what = "thin";
  } else {
    return 0;
  }
  snprintf(line1, cap1, "wall %.0f-%.0f mm %s", lo, hi, what);
  snprintf(line2, cap2, "%s", lower_half(r, lo, hi) ? "tilt into the pit" : "aim at the upper wall");
  return 1;
}

void pv_advice_refusal(const pv_result_t *r, pv_status_t st, pv_advice_t *out) {
  memset(out, 0, sizeof *out);
  char *why = out->why, *todo = out->todo, *text = out->sentence;
  const size_t cw = sizeof out->why, ct = sizeof out->todo, cs = sizeof out->sentence;
  snprintf(text, cs, "%s", pv_status_message(st));
  if (pv_advice_too_few_points(r, st)) {
    char pts[32];
    pv_advice_grouped(r->points_in, pts, sizeof pts);
    snprintf(why, cw, "too few points (%s)", pts);
    snprintf(todo, ct, "rescan slowly, all round");
    snprintf(text, cs,
             "the scan has too few points (%llu) to trace the wall all round; scan the whole pit "
             "again, slowly and closer, from every side",
             (unsigned long long)r->points_in);
    return;
  }
  switch (st) {
    case PV_ERR_WALL_GAP: {
      const int lower = lower_half(r, r->gap_from_mm, r->gap_to_mm);
      snprintf(why, cw, "wall %.0f-%.0f mm not seen", r->gap_from_mm, r->gap_to_mm);
      snprintf(todo, ct, "rescan: %s", lower ? "tilt into the pit" : "aim at the upper wall");
      snprintf(text, cs,
               "the wall from %.0f mm to %.0f mm above the floor was not seen well enough to "
               "trace its outline; scan that band again from several sides, %s",
               r->gap_from_mm, r->gap_to_mm,
               lower ? "tilting the scanner down into the pit" : "aiming at the upper wall");
      return;
    }
    case PV_ERR_NO_BOTTOM_PLANE:
      snprintf(why, cw, "floor not found");
      snprintf(todo, ct, "rescan: include the floor");
      return;
    case PV_ERR_NO_RIM:
      snprintf(why, cw, "rim not found");
      snprintf(todo, ct, "rescan: the rim all round");
      return;
    case PV_ERR_TOO_FEW_LAYERS:
      snprintf(why, cw, "too little wall seen");
      snprintf(todo, ct, "rescan the wall all round");
      return;
    case PV_ERR_DEPTH_EXCEEDS_CAPACITY:
      snprintf(why, cw, "pit deeper than the range");
      snprintf(todo, ct, "raise core.max_layers");
      return;
    case PV_ERR_NOT_A_PIT:
      snprintf(text, cs, "%s", pv_pit_check_message(r->failed_check));
      snprintf(todo, ct, "rescan the pit alone");
      switch (r->failed_check) {
        case PV_PIT_CHECK_POINTS_INSIDE:
          snprintf(why, cw, "%.0f%% of points in the void", 100 * r->check_value);
          return;
        case PV_PIT_CHECK_NARROW_MOUTH:
          snprintf(why, cw, "mouth %.0f%% of widest part", 100 * r->check_value);
          return;
        case PV_PIT_CHECK_TOO_WIDE:
          snprintf(why, cw, "wider than %.0f mm", 2 * r->check_limit);
          return;
        case PV_PIT_CHECK_OPENING_TILT:
          snprintf(why, cw, "opening faces away");
          snprintf(todo, ct, "rescan from above the pit");
          snprintf(text, cs,
                   "%s; hold the scanner above the pit, looking down into it, and scan again",
                   pv_pit_check_message(r->failed_check));
          return;
        case PV_PIT_CHECK_SECTIONS:
          snprintf(why, cw, "layer outlines inconsistent");
          return;
        case PV_PIT_CHECK_TOO_SMALL:
          snprintf(why, cw, "only %.3g cm3: not a test hole", r->check_value);
          snprintf(todo, ct, "check the scan's units");
          return;
        case PV_PIT_CHECK_DOUBLED_WALL:
        case PV_PIT_CHECK_DOUBLED_SPARSE_WALL:
        case PV_PIT_CHECK_DOUBLED_FLOOR:
        case PV_PIT_CHECK_DOUBLED_RIM:
          /* The scan holds the pit twice: the scanner lost its tracking. */
          snprintf(why, cw, "%s seen twice",
                   r->failed_check == PV_PIT_CHECK_DOUBLED_WALL ||
                           r->failed_check == PV_PIT_CHECK_DOUBLED_SPARSE_WALL
                       ? "wall"
                       : (r->failed_check == PV_PIT_CHECK_DOUBLED_FLOOR ? "floor" : "rim"));
          snprintf(todo, ct, "rescan in one steady pass");
          return;
        case PV_PIT_CHECK_OVER_MOUTH:
        case PV_PIT_CHECK_SHIFTED_WALL:
          /* Two passes shifted sideways: the scanner lost its tracking. */
          snprintf(why, cw, "passes shifted sideways");
          snprintf(todo, ct, "rescan in one steady pass");
          return;
        case PV_PIT_CHECK_THIN_TOP:
          /* Two passes apart in height: the scanner lost its tracking. */
          snprintf(why, cw, "passes apart in height");
          snprintf(todo, ct, "rescan in one steady pass");
          return;
        default:
          snprintf(why, cw, "does not look like a pit");
          snprintf(text, cs, "%s", pv_status_message(st));
          return;
      }
    default:
      snprintf(why, cw, "%s", pv_status_name(st));
      snprintf(todo, ct, "rescan; report if it recurs");
      return;
  }
}
