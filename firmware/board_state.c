/* The board's state machine (board_state.h). */
#include "board_state.h"

#include <string.h>

const char *pv_board_state_name(pv_board_state_t s) {
  static const char *const kNames[PV_BOARD_STATE_COUNT] = {
      "boot", "no_scanner", "idle", "scanning", "paused", "measuring", "result", "refused"};
  return (unsigned)s < PV_BOARD_STATE_COUNT ? kNames[s] : "?";
}

const char *pv_board_event_name(pv_board_event_t e) {
  static const char *const kNames[PV_EV_COUNT] = {
      "start_stop", "enter",    "back",     "scanner_arrived", "scanner_gone",
      "scan_ended", "tick",     "measured", "scan_failed"};
  return (unsigned)e < PV_EV_COUNT ? kNames[e] : "?";
}

void pv_board_init(pv_board_model_t *m) {
  memset(m, 0, sizeof *m);
  m->state = PV_BOARD_BOOT;
  m->live_status = PV_ERR_TOO_FEW_POINTS;
  m->result_status = PV_ERR_TOO_FEW_POINTS;
}

static unsigned begin_scan(pv_board_model_t *m) {
  m->state = PV_BOARD_SCANNING;
  m->armed = 0;
  m->stopping = 0;
  m->points = 0;
  m->scan_ms = 0;
  m->live_valid = 0;
  m->live_status = PV_ERR_TOO_FEW_POINTS;
  m->board_warnings = 0;
  m->message[0] = '\0';
  return PV_ACT_BEGIN_SCAN | PV_ACT_REDRAW;
}

static unsigned to_rest(pv_board_model_t *m) {
  m->state = m->scanner_present ? PV_BOARD_IDLE : PV_BOARD_NO_SCANNER;
  return PV_ACT_REDRAW;
}

unsigned pv_board_step(pv_board_model_t *m, pv_board_event_t ev) {
  /* Presence is tracked in every state. */
  if (ev == PV_EV_SCANNER_ARRIVED) m->scanner_present = 1;
  if (ev == PV_EV_SCANNER_GONE) m->scanner_present = 0;

  switch (m->state) {
    case PV_BOARD_BOOT:
      if (ev == PV_EV_SCANNER_ARRIVED || ev == PV_EV_SCANNER_GONE) return to_rest(m);
      return 0;

    case PV_BOARD_NO_SCANNER:
      if (ev == PV_EV_SCANNER_ARRIVED) return m->armed ? begin_scan(m) : to_rest(m);
      if (ev == PV_EV_START_STOP) {
        m->armed = !m->armed;
        return PV_ACT_REDRAW;
      }
      if (ev == PV_EV_BACK && m->armed) {
        m->armed = 0;
        return PV_ACT_REDRAW;
      }
      return 0;

    case PV_BOARD_IDLE:
      if (ev == PV_EV_START_STOP) return begin_scan(m);
      if (ev == PV_EV_SCANNER_GONE) return to_rest(m);
      if (ev == PV_EV_ENTER && m->have_result) {
        m->state = m->result_status == PV_OK ? PV_BOARD_RESULT : PV_BOARD_REFUSED;
        return PV_ACT_REDRAW;
      }
      return 0;

    case PV_BOARD_SCANNING:
      if (ev == PV_EV_TICK) return PV_ACT_ESTIMATE | PV_ACT_REDRAW;
      if (ev == PV_EV_START_STOP && !m->stopping) {
        m->stopping = 1;
        return PV_ACT_STOP_SCAN | PV_ACT_REDRAW;
      }
      if (ev == PV_EV_SCAN_ENDED) {
        m->state = PV_BOARD_MEASURING;
        return PV_ACT_MEASURE | PV_ACT_REDRAW;
      }
      if (ev == PV_EV_SCANNER_GONE) {
        m->state = PV_BOARD_PAUSED;
        return PV_ACT_REDRAW;
      }
      if (ev == PV_EV_SCAN_FAILED) return to_rest(m);
      return 0;

    case PV_BOARD_PAUSED:
      if (ev == PV_EV_SCANNER_ARRIVED) {
        /* The driver re-sends START on its own; the scan goes on. */
        if (!m->stopping) {
          m->state = PV_BOARD_SCANNING;
          return PV_ACT_REDRAW;
        }
        /* STOP was pressed before the unplug: the driver does not resume,
         * the end of the scan will not come; measure what arrived. */
        m->board_warnings |= PV_BOARD_WARN_ENDED_UNPLUGGED;
        m->state = PV_BOARD_MEASURING;
        return PV_ACT_MEASURE | PV_ACT_REDRAW;
      }
      if (ev == PV_EV_START_STOP) {
        m->board_warnings |= PV_BOARD_WARN_ENDED_UNPLUGGED;
        m->state = PV_BOARD_MEASURING;
        return PV_ACT_STOP_SCAN | PV_ACT_MEASURE | PV_ACT_REDRAW;
      }
      if (ev == PV_EV_TICK) return PV_ACT_REDRAW;
      return 0;

    case PV_BOARD_MEASURING:
      if (ev == PV_EV_MEASURED) {
        m->have_result = 1;
        m->state = m->result_status == PV_OK ? PV_BOARD_RESULT : PV_BOARD_REFUSED;
        return PV_ACT_REDRAW;
      }
      return 0;

    case PV_BOARD_RESULT:
    case PV_BOARD_REFUSED:
      if (ev == PV_EV_ENTER || ev == PV_EV_BACK) return to_rest(m);
      if (ev == PV_EV_START_STOP) {
        if (m->scanner_present) return begin_scan(m);
        m->armed = 1;
        m->state = PV_BOARD_NO_SCANNER;
        return PV_ACT_REDRAW;
      }
      if (ev == PV_EV_SCANNER_ARRIVED || ev == PV_EV_SCANNER_GONE) return PV_ACT_REDRAW;
      return 0;

    case PV_BOARD_STATE_COUNT:
      break;
  }
  return 0;
}
