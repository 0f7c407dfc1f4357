/* A measurement as the link carries it (pitvol/link_result.h). */
#include "pitvol/link_result.h"

#include <stdio.h>
#include <string.h>

#include "pitvol/user_input.h"

_Static_assert(PV_DENSITY_WET == pitvol_DensityFlag_DENSITY_WET, "density flags = protocol flags");
_Static_assert(PV_DENSITY_DRY == pitvol_DensityFlag_DENSITY_DRY, "density flags = protocol flags");
_Static_assert(PV_DENSITY_COMPACTION == pitvol_DensityFlag_DENSITY_COMPACTION, "density flags");
_Static_assert(PV_DENSITY_UNBOUNDED == pitvol_DensityFlag_DENSITY_UNBOUNDED, "density flags");
_Static_assert((int)PV_VERDICT_PASS == (int)pitvol_Verdict_VERDICT_PASS, "verdicts = protocol verdicts");
_Static_assert((int)PV_VERDICT_FAIL == (int)pitvol_Verdict_VERDICT_FAIL, "verdicts = protocol verdicts");
_Static_assert((int)PV_VERDICT_UNDECIDED == (int)pitvol_Verdict_VERDICT_UNDECIDED, "verdicts");

uint64_t pv_link_result_time(int64_t clock_unix_s) {
  return clock_unix_s >= PV_LINK_PLAUSIBLE_UNIX_S ? (uint64_t)clock_unix_s : 0u;
}

pv_link_status_t pv_link_record_apply(pv_link_record_t *rec, const pitvol_SetRecord *s, char *err,
                                      size_t cap) {
  pv_link_record_t next = *rec;
  if ((s->fields & pitvol_RecordField_RECORD_TEST_ID) &&
      pv_input_text("test id", s->test_id, next.test_id, sizeof next.test_id, err, cap) != PV_UI_OK)
    return PV_LINK_RECORD_TEXT;
  if ((s->fields & pitvol_RecordField_RECORD_LOCATION) &&
      pv_input_text("location", s->location, next.location, sizeof next.location, err, cap) !=
          PV_UI_OK)
    return PV_LINK_RECORD_TEXT;
  if ((s->fields & pitvol_RecordField_RECORD_OPERATOR) &&
      pv_input_text("operator", s->operator_name, next.operator_name, sizeof next.operator_name, err,
                    cap) != PV_UI_OK)
    return PV_LINK_RECORD_TEXT;
  if (s->fields & pitvol_RecordField_RECORD_MAX_DRY_DENSITY) {
    if (pv_input_check(PV_INPUT_MAX_DRY_KG_M3, s->max_dry_density_kg_m3, err, cap) != PV_UI_OK)
      return PV_LINK_RECORD_OUT_OF_RANGE;
    next.max_dry_density_kg_m3 = s->max_dry_density_kg_m3;
  }
  if (s->fields & pitvol_RecordField_RECORD_REQUIRED_COMPACTION) {
    if (pv_input_check(PV_INPUT_REQUIRED_PERCENT, s->required_compaction_percent, err, cap) !=
        PV_UI_OK)
      return PV_LINK_RECORD_OUT_OF_RANGE;
    next.required_compaction_percent = s->required_compaction_percent;
  }
  *rec = next;
  return PV_LINK_OK;
}

static void put_density(pitvol_Result *out, const pv_link_result_source_t *src) {
  const pv_density_t *d = src->density;
  out->has_density = true;
  pitvol_Density *p = &out->density;
  p->flags = d->flags;
  p->mass_g = src->mass_g;
  p->moisture_percent = (d->flags & PV_DENSITY_DRY) ? src->moisture_percent : 0;
  p->wet_kg_m3 = d->wet_kg_m3;
  p->wet_low_kg_m3 = d->wet_low_kg_m3;
  p->wet_high_kg_m3 = d->wet_high_kg_m3;
  p->dry_kg_m3 = d->dry_kg_m3;
  p->dry_low_kg_m3 = d->dry_low_kg_m3;
  p->dry_high_kg_m3 = d->dry_high_kg_m3;
  p->reference_max_dry_kg_m3 = (d->flags & PV_DENSITY_COMPACTION) && src->record
                                   ? src->record->max_dry_density_kg_m3
                                   : 0;
  p->compaction_percent = d->compaction_percent;
  p->compaction_low_percent = d->compaction_low_percent;
  p->compaction_high_percent = d->compaction_high_percent;
}

void pv_link_result_message(pitvol_Result *out, const pv_link_result_source_t *src) {
  static const pv_density_t no_density;
  const pv_result_t *r = src->result;
  const pv_density_t *d = src->density ? src->density : &no_density;
  const int measured = src->status == PV_OK;
  memset(out, 0, sizeof *out);
  out->time_unix_s = pv_link_result_time(src->clock_unix_s);
  out->status = (int32_t)src->status;
  snprintf(out->method, sizeof out->method, "%s", src->method ? src->method : "");
  if (measured) {
    out->volume_cm3 = r->volume_cm3;
    out->interval_cm3 = r->interval_cm3;
    out->depth_mm = r->depth_mm;
  } else if (src->status == PV_ERR_NOT_A_PIT) {
    out->failed_check = r->failed_check;
    out->check_value = r->check_value;
    out->check_limit = r->check_limit;
  } else if (src->status == PV_ERR_WALL_GAP) {
    out->gap_from_mm = r->gap_from_mm;
    out->gap_to_mm = r->gap_to_mm;
  }
  out->warnings = r->warnings;
  out->unseen_share = r->unseen_share;
  out->points_in = r->points_in;
  out->points_used = r->points_used;
  if (d->flags & PV_DENSITY_WET) put_density(out, src);
  if (src->record) {
    const pv_link_record_t *rec = src->record;
    pitvol_Record *o = &out->record;
    out->has_record = true;
    snprintf(o->test_id, sizeof o->test_id, "%s", rec->test_id);
    snprintf(o->location, sizeof o->location, "%s", rec->location);
    snprintf(o->operator_name, sizeof o->operator_name, "%s", rec->operator_name);
    o->required_compaction_percent = rec->required_compaction_percent;
    double within = 0;
    o->verdict = (pitvol_Verdict)pv_density_verdict(d, measured ? r->volume_cm3 : 0.0,
                                                    rec->required_compaction_percent, &within);
    o->decides_within_cm3 = within;
  }
}
