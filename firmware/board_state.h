/*
 * The board's state machine, without I/O: events in, actions out. The
 * event loop (board_app.c) turns buttons, USB state changes, the timer and
 * (later) serial commands into events, performs the actions it gets back,
 * and draws the screen of the current state from the model.
 *
 *   BOOT -> IDLE (scanner present) | NO_SCANNER
 *   NO_SCANNER --arrived--> IDLE, or SCANNING if START was pressed meanwhile
 *   IDLE --START--> SCANNING (tick: live estimate, redraw)
 *   SCANNING --STOP--> (scanner ends the scan) --ended--> MEASURING
 *   SCANNING --gone--> PAUSED --arrived--> SCANNING (points kept, resumes)
 *   PAUSED --STOP--> MEASURING (result carries "scan ended while unplugged")
 *   MEASURING --measured--> RESULT | REFUSED --ENTER/BACK--> IDLE,
 *                                             --START--> SCANNING
 *   IDLE --ENTER--> the last RESULT/REFUSED again
 */
#ifndef PV_BOARD_STATE_H
#define PV_BOARD_STATE_H

#include <stdint.h>

#include "pitvol/density.h"
#include "pitvol/pitvol.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pv_board_state {
  PV_BOARD_BOOT = 0,
  PV_BOARD_NO_SCANNER,
  PV_BOARD_IDLE,
  PV_BOARD_SCANNING,
  PV_BOARD_PAUSED,
  PV_BOARD_MEASURING,
  PV_BOARD_RESULT,
  PV_BOARD_REFUSED,
  PV_BOARD_STATE_COUNT
} pv_board_state_t;

typedef enum pv_board_event {
  PV_EV_START_STOP = 0, /* button, or serial "start"/"stop" */
  PV_EV_ENTER,
  PV_EV_BACK,
  PV_EV_SCANNER_ARRIVED,
  PV_EV_SCANNER_GONE,
  PV_EV_SCAN_ENDED,     /* the scanner sent END_OF_SCAN */
  PV_EV_TICK,           /* estimate_period_ms */
  PV_EV_MEASURED,       /* finish() is done: model.result_status says how */
  PV_EV_SCAN_FAILED,    /* the scan could not start: model.message says why */
  PV_EV_COUNT
} pv_board_event_t;

/* Actions for the event loop (bits). */
#define PV_ACT_BEGIN_SCAN (1u << 0) /* reset the session, START the scanner */
#define PV_ACT_STOP_SCAN  (1u << 1) /* STOP the scanner (it ends the scan) */
#define PV_ACT_ESTIMATE   (1u << 2) /* live estimate into model.live */
#define PV_ACT_MEASURE    (1u << 3) /* finish() into model.result (after drawing) */
#define PV_ACT_REDRAW     (1u << 4)

/* Board-level warnings on a result (beside the core's PV_WARN_* bits). */
#define PV_BOARD_WARN_ENDED_UNPLUGGED (1u << 0) /* measured what arrived before an unplug */

typedef struct pv_board_model {
  pv_board_state_t state;
  int scanner_present;
  int armed;             /* START pressed with no scanner: scan on arrival */
  int stopping;          /* STOP sent, waiting for END_OF_SCAN */
  uint64_t points;       /* points pushed in this scan */
  uint64_t scan_ms;      /* time scanning so far (PAUSED included) */
  pv_status_t live_status;
  int live_valid;        /* an estimate has been made in this scan */
  pv_result_t live;
  pv_status_t result_status;
  int have_result;
  pv_result_t result;
  uint32_t board_warnings;
  uint32_t dropped_events; /* events lost to a full queue since start: the
                              result screens show them */
  char message[128];     /* why a scan could not start, etc. */
  /* Density (docs/density.md): set over the serial link (SetMass, SetMoisture).
   * The mass belongs to one pit: a measured result uses it and clears it;
   * the moisture stays until changed. */
  int mass_set, moisture_set;
  double mass_g, moisture_percent;
  pv_density_t density;  /* of model.result; flags 0: no mass was set */
  /* The test record (SetRecord): the test id belongs to one pit, like the
   * mass; the verdict of model.result against the configuration's
   * required compaction. */
  char test_id[24];
  char result_test_id[24];     /* the test id model.result was taken under */
  pv_verdict_t verdict;
  double decides_within_cm3;   /* UNDECIDED: the interval that would decide */
  uint32_t result_id;    /* the result's record number in the log, 0: not logged */
} pv_board_model_t;

void pv_board_init(pv_board_model_t *m);
/* Applies one event; returns PV_ACT_* bits. */
unsigned pv_board_step(pv_board_model_t *m, pv_board_event_t ev);
const char *pv_board_state_name(pv_board_state_t s); /* "scanning" ... */
const char *pv_board_event_name(pv_board_event_t e);

#ifdef __cplusplus
}
#endif
#endif
