/*
 * The board's screens: one drawing per state from the model, into the
 * canvas (few words, large numbers, high contrast). docs/board.md shows
 * them. Drawing never allocates.
 */
#ifndef PV_BOARD_SCREENS_H
#define PV_BOARD_SCREENS_H

#include <stddef.h>

#include "board_config.h"
#include "board_state.h"
#include "pitvol/canvas.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pv_board_fonts {
  pv_font_t body; /* 10x20 */
  pv_font_t big;  /* 16x32; x2 for the result's digits */
} pv_board_fonts_t;

/* A wall band counts as seen from this share of coverage on. */
#define PV_BOARD_SEEN_SHARE 0.5f

void pv_board_draw(pv_canvas_t *c, const pv_board_model_t *m, const pv_board_fonts_t *f,
                   pv_board_units_t units);

/* The hint for the widest run of unseen wall bands of an estimate
 * (coverage[] below PV_BOARD_SEEN_SHARE, or the core's wall gap):
 * "wall 55-90 mm not seen" / "tilt into the pit" (heights above the floor).
 * Returns 0 (and empty lines) when every band is seen. */
int pv_board_coverage_hint(const pv_result_t *r, pv_status_t st, char *line1, size_t cap1,
                           char *line2, size_t cap2);

/* Why the core refused, in few words, and what to rescan. */
void pv_board_refusal_text(const pv_result_t *r, pv_status_t st, char *why, size_t cap_why,
                           char *todo, size_t cap_todo);

#ifdef __cplusplus
}
#endif
#endif
