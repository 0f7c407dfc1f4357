/*
 * A measurement as the link carries it (pitvol.Result, docs/protocol/serial.md):
 * the one mapping from the core's result, the density and the test record
 * to the message, used by the link server's applications (the board,
 * the monitor's test device) so that both send the same bits.
 */
#ifndef PITVOL_LINK_RESULT_H
#define PITVOL_LINK_RESULT_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/density.h"
#include "pitvol/link.h"
#include "pitvol/pitvol.h"
#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 2024-01-01T00:00:00Z: any earlier clock reading is an unset clock. */
#define PV_LINK_PLAUSIBLE_UNIX_S INT64_C(1704067200)

/* A result's time_unix_s from the board clock's reading: a board without a
 * battery-backed clock or network time starts in 1970, and such a reading
 * is no date: 0, "clock not set" (pitvol-monitor prints clock-not-set). */
uint64_t pv_link_result_time(int64_t clock_unix_s);

/* The field density test a result belongs to (docs/board.md, "The test
 * record"): set over the link (SetRecord) or by the board's configuration. */
typedef struct pv_link_record {
  char test_id[sizeof(((pitvol_Record *)0)->test_id)];
  char location[sizeof(((pitvol_Record *)0)->location)];
  char operator_name[sizeof(((pitvol_Record *)0)->operator_name)];
  double max_dry_density_kg_m3;        /* 0: none */
  double required_compaction_percent;  /* 0: none */
} pv_link_record_t;

/* Applies the fields a SetRecord names, all or none: PV_LINK_OK, or
 * PV_LINK_RECORD_TEXT (too long, a control character) or
 * PV_LINK_RECORD_OUT_OF_RANGE with one line in err naming the field. */
PV_NODISCARD pv_link_status_t pv_link_record_apply(pv_link_record_t *rec,
                                                   const pitvol_SetRecord *s, char *err,
                                                   size_t cap);

/* What a Result is made of. */
typedef struct pv_link_result_source {
  pv_status_t status;              /* what pv_session_finish said */
  const pv_result_t *result;       /* its result */
  const char *method;              /* pv_method_name() of the method that measured */
  int64_t clock_unix_s;            /* the board clock when the result was taken */
  const pv_density_t *density;     /* of this result (flags 0 or NULL: none) */
  double mass_g, moisture_percent; /* the inputs of that density */
  const pv_link_record_t *record;  /* the record the result was taken under (NULL: none);
                                      its maximum dry density is the density's reference */
} pv_link_result_source_t;

/* Fills out (id 0: the log gives the id). A result without a volume
 * (status other than PV_OK) carries no volume, interval or depth, whatever
 * the core left in them, and says why instead: the plausibility check that
 * refused a PV_ERR_NOT_A_PIT with its figure and limit, the band of a
 * PV_ERR_WALL_GAP. */
void pv_link_result_message(pitvol_Result *out, const pv_link_result_source_t *src);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_LINK_RESULT_H */
