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

void pv_board_draw(pv_canvas_t *c, const pv_board_model_t *m, const pv_board_fonts_t *f,
                   pv_board_units_t units);

#ifdef __cplusplus
}
#endif
#endif
