// Names and user-facing messages of pv_status_t.
#include "pitvol/pitvol.h"

extern "C" const char *pv_status_name(pv_status_t status) {
  switch (status) {
    case PV_OK: return "PV_OK";
    case PV_ERR_INVALID_ARGUMENT: return "PV_ERR_INVALID_ARGUMENT";
    case PV_ERR_INVALID_CONFIG: return "PV_ERR_INVALID_CONFIG";
    case PV_ERR_BLOCK_TOO_SMALL: return "PV_ERR_BLOCK_TOO_SMALL";
    case PV_ERR_BLOCK_MISALIGNED: return "PV_ERR_BLOCK_MISALIGNED";
    case PV_ERR_WRONG_STATE: return "PV_ERR_WRONG_STATE";
    case PV_ERR_TOO_FEW_POINTS: return "PV_ERR_TOO_FEW_POINTS";
    case PV_ERR_NO_BOTTOM_PLANE: return "PV_ERR_NO_BOTTOM_PLANE";
    case PV_ERR_NO_RIM: return "PV_ERR_NO_RIM";
    case PV_ERR_TOO_FEW_LAYERS: return "PV_ERR_TOO_FEW_LAYERS";
    case PV_ERR_DEPTH_EXCEEDS_CAPACITY: return "PV_ERR_DEPTH_EXCEEDS_CAPACITY";
    case PV_ERR_OUT_OF_MEMORY: return "PV_ERR_OUT_OF_MEMORY";
    case PV_ERR_INTERNAL: return "PV_ERR_INTERNAL";
    case PV_ERR_WALL_GAP: return "PV_ERR_WALL_GAP";
    case PV_ERR_NOT_A_PIT: return "PV_ERR_NOT_A_PIT";
  }
  return "PV_ERR_UNKNOWN";
}

extern "C" const char *pv_status_message(pv_status_t status) {
  switch (status) {
    case PV_OK:
      return "measured";
    case PV_ERR_INVALID_ARGUMENT:
      return "a NULL pointer or out-of-range value was passed to the core; "
             "this is a caller bug";
    case PV_ERR_INVALID_CONFIG:
      return "a configuration value is out of range; check the named field "
             "against docs/method.md";
    case PV_ERR_BLOCK_TOO_SMALL:
      return "the memory block is smaller than pv_session_size() asked for";
    case PV_ERR_BLOCK_MISALIGNED:
      return "the memory block must be aligned to PV_BLOCK_ALIGN bytes";
    case PV_ERR_WRONG_STATE:
      return "the session is finished; call reset before the next scan";
    case PV_ERR_TOO_FEW_POINTS:
      return "the scan has too few valid points to measure; rescan the pit";
    case PV_ERR_NO_BOTTOM_PLANE:
      return "no pit bottom plane was found to level the scan; scan the "
             "bottom of the pit fully, or check the file holds one pit";
    case PV_ERR_NO_RIM:
      return "the rim (top edge) of the pit could not be found; scan the "
             "whole rim and some ground around it";
    case PV_ERR_TOO_FEW_LAYERS:
      return "too few depth layers have a closed wall contour; scan the "
             "walls all around, from every side";
    case PV_ERR_DEPTH_EXCEEDS_CAPACITY:
      return "the pit is deeper than the configured depth range "
             "(max_layers x layer_mm); raise max_layers";
    case PV_ERR_OUT_OF_MEMORY:
      return "the bounded working memory for finishing was not available";
    case PV_ERR_INTERNAL:
      return "internal error in the core; please report it with the scan file";
    case PV_ERR_WALL_GAP:
      return "a band of the pit wall has too few points to trace its outline "
             "(the band is given in gap_from_mm/gap_to_mm above the bottom); "
             "scan that part of the wall again, closer and from several sides";
    case PV_ERR_NOT_A_PIT:
      return "the points do not look like one pit (a floor, and a wall "
             "closing around it up to a rim); check that the file holds one "
             "pit scan and rescan it";
  }
  return "unknown status";
}

extern "C" const char *pv_pit_check_name(uint32_t check) {
  switch (check) {
    case PV_PIT_CHECK_NONE: return "PV_PIT_CHECK_NONE";
    case PV_PIT_CHECK_NO_POINTS: return "PV_PIT_CHECK_NO_POINTS";
    case PV_PIT_CHECK_POINTS_INSIDE: return "PV_PIT_CHECK_POINTS_INSIDE";
    case PV_PIT_CHECK_NARROW_MOUTH: return "PV_PIT_CHECK_NARROW_MOUTH";
    case PV_PIT_CHECK_TOO_WIDE: return "PV_PIT_CHECK_TOO_WIDE";
    case PV_PIT_CHECK_OPENING_TILT: return "PV_PIT_CHECK_OPENING_TILT";
    case PV_PIT_CHECK_SECTIONS: return "PV_PIT_CHECK_SECTIONS";
    case PV_PIT_CHECK_DOUBLED_WALL: return "PV_PIT_CHECK_DOUBLED_WALL";
    case PV_PIT_CHECK_DOUBLED_FLOOR: return "PV_PIT_CHECK_DOUBLED_FLOOR";
    case PV_PIT_CHECK_TOO_SMALL: return "PV_PIT_CHECK_TOO_SMALL";
    case PV_PIT_CHECK_DOUBLED_RIM: return "PV_PIT_CHECK_DOUBLED_RIM";
    case PV_PIT_CHECK_THIN_TOP: return "PV_PIT_CHECK_THIN_TOP";
    case PV_PIT_CHECK_OVER_MOUTH: return "PV_PIT_CHECK_OVER_MOUTH";
    case PV_PIT_CHECK_SHIFTED_WALL: return "PV_PIT_CHECK_SHIFTED_WALL";
    case PV_PIT_CHECK_DOUBLED_SPARSE_WALL: return "PV_PIT_CHECK_DOUBLED_SPARSE_WALL";
    default: return "PV_PIT_CHECK_UNKNOWN";
  }
}

extern "C" const char *pv_pit_check_message(uint32_t check) {
  switch (check) {
    case PV_PIT_CHECK_NONE: return "every plausibility check passed";
    case PV_PIT_CHECK_NO_POINTS:
      return "no point lies near the modelled floor and wall";
    case PV_PIT_CHECK_POINTS_INSIDE:
      return "too many points lie inside the space the wall encloses (an open "
             "pit's void is empty: a random cloud, a mound, two pits or objects "
             "in the pit)";
    case PV_PIT_CHECK_NARROW_MOUTH:
      return "the section at the rim is much smaller than the widest section "
             "below it (a closed shell, not an open pit)";
    case PV_PIT_CHECK_TOO_WIDE:
      return "the wall reaches the edge of the measuring grids (wider than "
             "surface_max_radius_mm: a trench, or a scan of more than one pit)";
    case PV_PIT_CHECK_OPENING_TILT:
      return "the opening faces away from the scanner (a mound, or the scanner "
             "frame upside down; max_opening_tilt_deg)";
    case PV_PIT_CHECK_SECTIONS:
      return "the layer sections integrate to no volume a pit of that depth "
             "and width can hold (at most the largest section times the "
             "depth, and more than 0): they jump too much from layer to "
             "layer to be one pit's wall";
    case PV_PIT_CHECK_DOUBLED_WALL:
    case PV_PIT_CHECK_DOUBLED_SPARSE_WALL:
      return "the wall appears twice, a few mm apart: the scan holds the pit "
             "twice, registered apart (the scanner lost its tracking during "
             "the scan); scan the pit again in one steady pass";
    case PV_PIT_CHECK_DOUBLED_FLOOR:
      return "the floor appears twice, a few to 40 mm apart: the scan holds "
             "the pit twice, registered apart (the scanner lost its tracking "
             "during the scan), or loose soil covers the floor; clear the "
             "floor and scan the pit again in one steady pass";
    case PV_PIT_CHECK_TOO_SMALL:
      return "smaller than any test hole: a scan in centimetres or metres "
             "read as millimetres (give the file's units), or not a test pit";
    case PV_PIT_CHECK_DOUBLED_RIM:
      return "the ground (or the lip) around the pit appears twice, 8 to 40 mm "
             "apart in height: the scan holds the pit twice, registered apart "
             "(the scanner lost its tracking during the scan); scan the pit "
             "again in one steady pass";
    case PV_PIT_CHECK_THIN_TOP:
      return "the top of the wall was seen by one pass only, the wall below it "
             "by two: the passes lie apart in height (the scanner lost its "
             "tracking during the scan); scan the pit again in one steady pass";
    case PV_PIT_CHECK_OVER_MOUTH:
      return "the ground (or the top of the wall) lies over the pit's mouth, "
             "inside the wall: the scan holds the pit twice, shifted sideways "
             "(the scanner lost its tracking during the scan); scan the pit "
             "again in one steady pass";
    case PV_PIT_CHECK_SHIFTED_WALL:
      return "a second wall lies beside the first, furthest apart on two "
             "opposite sides and nowhere across them: the scan holds the pit twice, "
             "shifted sideways (the scanner lost its tracking during the "
             "scan); scan the pit again in one steady pass";
    default: return "unknown check";
  }
}

namespace {

struct WarningText {
  uint32_t bit;
  const char *name, *message, *short_text;
};

// The one table of warning texts (pitvol.h): pitvol measure, the report,
// the board's screens and pitvol-monitor all read it.
constexpr WarningText kWarnings[] = {
    {PV_WARN_POINTS_THINNED, "PV_WARN_POINTS_THINNED",
     "dense parts of the scan were thinned to fit the fixed memory (by design; the accuracy "
     "figures include it)",
     "dense bins thinned"},
    {PV_WARN_INVALID_POINTS, "PV_WARN_INVALID_POINTS",
     "points with NaN, infinite or absurd coordinates were skipped; if there are many, check "
     "the scanner's export",
     "bad points skipped"},
    {PV_WARN_OUT_OF_RANGE, "PV_WARN_OUT_OF_RANGE",
     "more than 1 % of the points lie outside the depth range and were not used; if the pit is "
     "deeper than max_layers x layer_mm, raise max_layers",
     "points out of range"},
    {PV_WARN_LAYERS_REJECTED, "PV_WARN_LAYERS_REJECTED",
     "more than 5 % of the layers were rejected as outliers; find the band in the report's area "
     "plot and rescan it if the wall there was not seen",
     "many layers rejected"},
    {PV_WARN_LARGE_TILT, "PV_WARN_LARGE_TILT",
     "the pit's floor is tilted more than 30 deg from the scanner's view; check in the report's "
     "side view that the levelled floor is the pit's floor",
     "large tilt"},
    {PV_WARN_SPARSE_LAYERS, "PV_WARN_SPARSE_LAYERS",
     "more than 10 % of the layers had too few wall points; scan the wall closer and from every "
     "side",
     "sparse layers"},
    {PV_WARN_BRIDGED, "PV_WARN_BRIDGED",
     "part of the wall was not seen and was bridged from the wall around it (unseen_share of "
     "the volume, inside the interval); to narrow the interval, rescan that band of the wall",
     "unseen wall bridged"},
};

const WarningText *warning_row(uint32_t bit) {
  for (const WarningText &w : kWarnings) {
    if (w.bit == bit) return &w;
  }
  return nullptr;
}

}  // namespace

extern "C" const char *pv_warning_name(uint32_t bit) {
  const WarningText *w = warning_row(bit);
  return w != nullptr ? w->name : nullptr;
}

extern "C" const char *pv_warning_message(uint32_t bit) {
  const WarningText *w = warning_row(bit);
  return w != nullptr ? w->message : nullptr;
}

extern "C" const char *pv_warning_short(uint32_t bit) {
  const WarningText *w = warning_row(bit);
  return w != nullptr ? w->short_text : nullptr;
}

extern "C" uint32_t pv_warnings_attention(uint32_t warnings, double unseen_share) {
  uint32_t a = warnings & PV_WARN_ALL & ~PV_WARN_POINTS_THINNED;
  if (!(unseen_share >= PV_WARN_BRIDGED_SHARE)) a &= ~PV_WARN_BRIDGED;
  return a;
}
