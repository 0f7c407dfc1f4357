/* Why a result has no volume, on the wire (docs/protocol/serial.md,
 * Result.failed_check .. gap_to_mm). Header-only: the board application and
 * the serial test device (tests/monitor/pv_test_device.cpp) fill the same
 * fields by the same rule. */
#ifndef PV_BOARD_REFUSAL_H
#define PV_BOARD_REFUSAL_H

#include "pitvol/link.h"
#include "pitvol/pitvol.h"

/* The refusal's detail from the core's result: the plausibility check that
 * refused a PV_ERR_NOT_A_PIT with its figure and limit, the band of a
 * PV_ERR_WALL_GAP; left zero for any other status. */
static inline void pv_board_result_refusal(pitvol_Result *out, pv_status_t status,
                                           const pv_result_t *r) {
  if (status == PV_ERR_NOT_A_PIT) {
    out->failed_check = r->failed_check;
    out->check_value = r->check_value;
    out->check_limit = r->check_limit;
  } else if (status == PV_ERR_WALL_GAP) {
    out->gap_from_mm = r->gap_from_mm;
    out->gap_to_mm = r->gap_to_mm;
  }
}

#endif
