/* The field density test a result belongs to (docs/board.md, "The test
 * record"): test number, location, operator, maximum dry density and
 * required compaction, set over the link (SetRecord) or by the board's
 * configuration, and the verdict of a result against them. Header-only:
 * the board application and the serial test device
 * (tests/monitor/pv_test_device.cpp) apply and fill them by the same rule. */
#ifndef PV_BOARD_RECORD_H
#define PV_BOARD_RECORD_H

#include <stdio.h>
#include <string.h>

#include "pitvol/density.h"
#include "pitvol/link.h"
#include "pitvol/user_input.h"

#ifdef __cplusplus
#define PV_BOARD_RECORD_ASSERT static_assert
#else
#define PV_BOARD_RECORD_ASSERT _Static_assert
#endif
PV_BOARD_RECORD_ASSERT((int)PV_VERDICT_PASS == (int)pitvol_Verdict_VERDICT_PASS, "verdicts = protocol verdicts");
PV_BOARD_RECORD_ASSERT((int)PV_VERDICT_FAIL == (int)pitvol_Verdict_VERDICT_FAIL, "verdicts = protocol verdicts");
PV_BOARD_RECORD_ASSERT((int)PV_VERDICT_UNDECIDED == (int)pitvol_Verdict_VERDICT_UNDECIDED, "verdicts");

typedef struct pv_board_record {
  char test_id[sizeof(((pitvol_Record *)0)->test_id)];
  char location[sizeof(((pitvol_Record *)0)->location)];
  char operator_name[sizeof(((pitvol_Record *)0)->operator_name)];
  double max_dry_density_kg_m3;        /* 0: none */
  double required_compaction_percent;  /* 0: none */
} pv_board_record_t;

/* Applies the fields a SetRecord names, all or none: 0, or -1 with one
 * line in err (a control character, a value outside its range). */
static inline int pv_board_record_apply(pv_board_record_t *rec, const pitvol_SetRecord *s, char *err,
                                        size_t cap) {
  pv_board_record_t next = *rec;
  if ((s->fields & pitvol_RecordField_RECORD_TEST_ID) &&
      pv_input_text("test id", s->test_id, next.test_id, sizeof next.test_id, err, cap) != 0)
    return -1;
  if ((s->fields & pitvol_RecordField_RECORD_LOCATION) &&
      pv_input_text("location", s->location, next.location, sizeof next.location, err, cap) != 0)
    return -1;
  if ((s->fields & pitvol_RecordField_RECORD_OPERATOR) &&
      pv_input_text("operator", s->operator_name, next.operator_name, sizeof next.operator_name, err,
                    cap) != 0)
    return -1;
  if (s->fields & pitvol_RecordField_RECORD_MAX_DRY_DENSITY) {
    if (pv_input_check(PV_INPUT_MAX_DRY_KG_M3, s->max_dry_density_kg_m3, err, cap) != 0) return -1;
    next.max_dry_density_kg_m3 = s->max_dry_density_kg_m3;
  }
  if (s->fields & pitvol_RecordField_RECORD_REQUIRED_COMPACTION) {
    if (pv_input_check(PV_INPUT_REQUIRED_PERCENT, s->required_compaction_percent, err, cap) != 0) return -1;
    next.required_compaction_percent = s->required_compaction_percent;
  }
  *rec = next;
  return 0;
}

/* The result's record: the header as set, the verdict of density d (of a
 * volume volume_cm3) against the requirement. */
static inline void pv_board_result_record(pitvol_Result *out, const pv_board_record_t *rec,
                                          const pv_density_t *d, double volume_cm3) {
  pitvol_Record *r = &out->record;
  out->has_record = true;
  snprintf(r->test_id, sizeof r->test_id, "%s", rec->test_id);
  snprintf(r->location, sizeof r->location, "%s", rec->location);
  snprintf(r->operator_name, sizeof r->operator_name, "%s", rec->operator_name);
  r->required_compaction_percent = rec->required_compaction_percent;
  double within = 0;
  r->verdict = (pitvol_Verdict)pv_density_verdict(d, volume_cm3, rec->required_compaction_percent, &within);
  r->decides_within_cm3 = within;
}

#endif
