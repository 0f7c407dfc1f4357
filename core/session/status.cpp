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
