/*
 * What a scan without a volume tells the technician, from the check that
 * failed: too few points, an unseen band of wall (which, and where to
 * aim), the opening's tilt, a doubled scan, ... One rule for the board's
 * REFUSED and SCANNING screens, `pitvol measure`, the report and
 * pitvol-monitor, so the advice cannot differ between them.
 */
#ifndef PITVOL_ADVICE_H
#define PITVOL_ADVICE_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/pitvol.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A band counts as seen from this share of its wall on (the board's green
 * bar); under PV_ADVICE_UNSEEN_SHARE it is not seen (red). */
#define PV_ADVICE_SEEN_SHARE 0.8f
#define PV_ADVICE_UNSEEN_SHARE 0.5f
/* Fewer points than this cannot describe a test pit's wall: the advice is
 * to scan longer, whatever band the core names. */
#define PV_ADVICE_FEW_POINTS 30000u

typedef struct pv_advice {
  char why[64];        /* a screen line: "too few points (5 837)" */
  char todo[64];       /* a screen line: "rescan slowly, all round" */
  char sentence[320];  /* for the CLI, the report, the monitor */
} pv_advice_t;

/* A count with its thousands apart ("301 989"), as the board's screens and
 * the advice print it: easier to read at a glance. */
void pv_advice_grouped(uint64_t v, char *out, size_t cap);

/* The advice for a result whose status st is not PV_OK. */
void pv_advice_refusal(const pv_result_t *r, pv_status_t st, pv_advice_t *out);

/* 1 when the scan is thin everywhere rather than missing one band: fewer
 * than PV_ADVICE_FEW_POINTS points, the status PV_ERR_TOO_FEW_POINTS, a
 * wall gap over 80 % of the depth, or three quarters of the coverage
 * bands or more under PV_ADVICE_SEEN_SHARE. */
int pv_advice_too_few_points(const pv_result_t *r, pv_status_t st);

/* While scanning (a live estimate r with status st): the widest run of
 * bands under PV_ADVICE_UNSEEN_SHARE ("wall 0-93 mm not seen"), else under
 * PV_ADVICE_SEEN_SHARE ("wall 0-93 mm thin"), or the core's wall gap,
 * as heights above the floor, and where to aim. 0 (lines empty) when
 * every band is seen: the scan may stop. */
int pv_advice_live(const pv_result_t *r, pv_status_t st, char *line1, size_t cap1, char *line2,
                   size_t cap2);

#ifdef __cplusplus
}
#endif
#endif
