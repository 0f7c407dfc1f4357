/*
 * The board's screens (board_screens.h). Layout for 320 x 240 and up:
 * a coloured title bar (36 px, the state in 16x32 letters), the body in
 * 10x20 text, the button legend on the last line. Numbers that matter
 * are the largest thing on the screen.
 */
#include "board_screens.h"

#include "pitvol/advice.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define TITLE_H 36
#define MARGIN 8
#define LINE_H 22

#define DEG "\xC2\xB0"  /* degree sign, UTF-8 */
#define CUBED "\xC2\xB3"
#define PLUSMINUS "\xC2\xB1"

static void title(pv_canvas_t *c, const pv_board_fonts_t *f, const char *text, pv_color_t ground,
                  pv_color_t ink, const char *right) {
  pv_canvas_fill(c, 0, 0, c->width, TITLE_H, ground);
  pv_canvas_text(c, &f->big, 1, MARGIN, 2, ink, text);
  if (right != NULL) {
    const int w = pv_text_width(&f->body, 1, right);
    pv_canvas_text(c, &f->body, 1, c->width - MARGIN - w, 8, ink, right);
  }
}

static int line(pv_canvas_t *c, const pv_font_t *font, int y, pv_color_t ink, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static int line(pv_canvas_t *c, const pv_font_t *font, int y, pv_color_t ink, const char *fmt, ...) {
  char buf[96];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  pv_canvas_text(c, font, 1, MARGIN, y, ink, buf);
  return y + (int)font->height_px + 2;
}

static void legend(pv_canvas_t *c, const pv_board_fonts_t *f, const char *text) {
  const int y = c->height - LINE_H;
  pv_canvas_fill(c, 0, y - 2, c->width, LINE_H + 2, PV_COLOR_BLACK);
  pv_canvas_text(c, &f->body, 1, MARGIN, y, PV_COLOR_WHITE, text);
}

static const char *usb_word(const pv_board_model_t *m) { return m->scanner_present ? "USB ok" : "no USB"; }

/* "11712.8" (cm3) or "11.713" (l); unit text "cm³" or "l". */
static void volume_text(double cm3, pv_board_units_t units, char *num, size_t cap,
                        const char **unit) {
  if (units == PV_UNITS_LITRE) {
    snprintf(num, cap, "%.3f", cm3 / 1000.0);
    *unit = "l";
  } else {
    snprintf(num, cap, "%.1f", cm3);
    *unit = "cm" CUBED;
  }
}

/* Coverage column: band 0 (floor) at the bottom, the rim at the top. */
static void coverage_bars(pv_canvas_t *c, const pv_board_fonts_t *f, const pv_board_model_t *m,
                          int x, int y_top, int y_bottom, int w) {
  pv_canvas_text(c, &f->body, 1, x, y_top, PV_COLOR_BLACK, "wall");
  y_top += LINE_H;
  const pv_result_t *r = &m->live;
  const int n = PV_COVERAGE_BANDS;
  const int band_h = (y_bottom - y_top) / n;
  pv_canvas_fill(c, x - 1, y_bottom - n * band_h - 1, w + 2, n * band_h + 2, PV_COLOR_BLACK);
  const int have = m->live_valid && r->coverage_bands == (uint32_t)n;
  for (int b = 0; b < n; ++b) {
    const int y = y_bottom - (b + 1) * band_h;
    pv_canvas_fill(c, x, y, w, band_h - 1, PV_COLOR_WHITE);
    if (!have) continue;
    float share = r->coverage[b];
    share = share < 0 ? 0 : share > 1 ? 1 : share;
    const pv_color_t col = share >= PV_ADVICE_SEEN_SHARE ? PV_COLOR_GREEN
                           : share >= PV_ADVICE_UNSEEN_SHARE ? PV_COLOR_AMBER
                                                          : PV_COLOR_RED;
    const int len = (int)lrintf(share * (float)w);
    pv_canvas_fill(c, x, y, len > 0 ? len : 1, band_h - 1, col);
  }
  if (have) {
    char buf[PV_COVERAGE_BANDS * 5 + 16];
    size_t o = 0;
    for (int b = 0; b < n; ++b) o += (size_t)snprintf(buf + o, sizeof buf - o, "%s%.2f", b ? " " : "", r->coverage[b]);
    pv_canvas_note(c, "coverage %s", buf);
  } else {
    pv_canvas_note(c, "coverage none");
  }
}

static const char *live_hint(pv_status_t st) {
  switch (st) {
    case PV_ERR_NO_BOTTOM_PLANE: return "scan the floor";
    case PV_ERR_NO_RIM: return "scan the rim all round";
    case PV_ERR_TOO_FEW_LAYERS: return "scan the wall all round";
    default: return "keep scanning";
  }
}

static void draw_scanning(pv_canvas_t *c, const pv_board_model_t *m, const pv_board_fonts_t *f,
                          pv_board_units_t units) {
  title(c, f, "SCANNING", PV_COLOR_BLUE, PV_COLOR_WHITE, usb_word(m));
  const int bars_w = 48, bars_x = c->width - MARGIN - bars_w;
  coverage_bars(c, f, m, bars_x, TITLE_H + 6, c->height - LINE_H - 10, bars_w);
  int y = TITLE_H + 8;
  char num[32], pts[32];
  const char *unit = "";
  const int estimate_ok = m->live_valid && (m->live_status == PV_OK || m->live_status == PV_ERR_WALL_GAP);
  if (estimate_ok && m->live.volume_cm3 > 0) {
    volume_text(m->live.volume_cm3, units, num, sizeof num, &unit);
    char big[48];
    snprintf(big, sizeof big, "~%s %s", num, unit);
    pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, big);
    y += 36;
    y = line(c, &f->body, y, PV_COLOR_BLACK, "depth %.0f mm", m->live.depth_mm);
  } else {
    pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_GREY, "--- ");
    y += 36;
    y = line(c, &f->body, y, PV_COLOR_GREY, "depth --");
  }
  pv_advice_grouped(m->points, pts, sizeof pts);
  y = line(c, &f->body, y, PV_COLOR_BLACK, "points %s", pts);
  const unsigned s = (unsigned)(m->scan_ms / 1000u);
  y = line(c, &f->body, y, PV_COLOR_BLACK, "time %u:%02u", s / 60u, s % 60u);
  (void)y;
  char h1[64], h2[64];
  const int hint_y = c->height - LINE_H - 8 - 2 * LINE_H;
  if (m->stopping) {
    line(c, &f->body, hint_y + LINE_H, PV_COLOR_BLACK, "stopping...");
  } else if (m->live_valid && pv_advice_live(&m->live, m->live_status, h1, sizeof h1, h2, sizeof h2)) {
    line(c, &f->body, hint_y, PV_COLOR_RED, "%s", h1);
    line(c, &f->body, hint_y + LINE_H, PV_COLOR_RED, "%s", h2);
  } else if (m->live_valid && m->live_status == PV_OK && m->live.coverage_bands == PV_COVERAGE_BANDS) {
    /* Only with every band green (pv_advice_live found none thin). */
    line(c, &f->body, hint_y + LINE_H, PV_COLOR_GREEN, "wall seen: STOP");
  } else {
    line(c, &f->body, hint_y + LINE_H, PV_COLOR_BLACK, "%s", live_hint(m->live_status));
  }
  legend(c, f, "STOP: end scan and measure");
}

/* Wet/dry density in g/cm³ (three decimals: 1 kg/m³) and the relative
 * compaction with its range from the volume's interval, when a mass was
 * set. "compaction 100.8% (98.9-102.8)" is 30 characters: fits 320 px. */
static int density_lines(pv_canvas_t *c, const pv_board_fonts_t *f, const pv_board_model_t *m, int y) {
  const pv_density_t *d = &m->density;
  if (!(d->flags & PV_DENSITY_WET)) return y;
  if (d->flags & PV_DENSITY_DRY) {
    y = line(c, &f->body, y, PV_COLOR_BLACK, "wet %.3f dry %.3f g/cm" CUBED,
             pv_density_kg_m3_to_g_cm3(d->wet_kg_m3), pv_density_kg_m3_to_g_cm3(d->dry_kg_m3));
  } else {
    y = line(c, &f->body, y, PV_COLOR_BLACK, "wet %.3f g/cm" CUBED " (no moisture)",
             pv_density_kg_m3_to_g_cm3(d->wet_kg_m3));
  }
  if (d->flags & PV_DENSITY_COMPACTION) {
    if (d->flags & PV_DENSITY_UNBOUNDED) {
      y = line(c, &f->body, y, PV_COLOR_BLACK, "compaction %.1f%% (%.1f-?)", d->compaction_percent,
               d->compaction_low_percent);
    } else if (d->compaction_low_percent == d->compaction_high_percent) { /* no interval */
      y = line(c, &f->body, y, PV_COLOR_BLACK, "compaction %.1f%%", d->compaction_percent);
    } else {
      y = line(c, &f->body, y, PV_COLOR_BLACK, "compaction %.1f%% (%.1f-%.1f)",
               d->compaction_percent, d->compaction_low_percent, d->compaction_high_percent);
    }
  }
  if (m->verdict != PV_VERDICT_NONE) {
    /* The test's verdict, and for UNDECIDED what would decide it. */
    const pv_color_t ink = m->verdict == PV_VERDICT_PASS ? PV_COLOR_GREEN
                           : m->verdict == PV_VERDICT_FAIL ? PV_COLOR_RED : PV_COLOR_AMBER;
    if (m->verdict == PV_VERDICT_UNDECIDED) {
      y = line(c, &f->body, y, ink, "UNDECIDED: need " PLUSMINUS "%.0f cm" CUBED, m->decides_within_cm3);
    } else {
      y = line(c, &f->body, y, ink, "%s %s", m->result_test_id[0] ? m->result_test_id : "test",
               pv_verdict_name(m->verdict));
    }
    pv_canvas_note(c, "verdict %s decides_within_cm3=%.17g test_id=%s", pv_verdict_name(m->verdict),
                   m->decides_within_cm3, m->result_test_id);
  }
  pv_canvas_note(c, "density flags=0x%x wet_kg_m3=%.17g dry_kg_m3=%.17g compaction_percent=%.17g",
                 d->flags, d->wet_kg_m3, d->dry_kg_m3, d->compaction_percent);
  return y;
}

static void draw_result(pv_canvas_t *c, const pv_board_model_t *m, const pv_board_fonts_t *f,
                        pv_board_units_t units) {
  const pv_result_t *r = &m->result;
  /* Amber title only for flags that change how far to trust the number. */
  const int warn = (pv_warnings_attention(r->warnings, r->unseen_share) & (PV_WARN_BRIDGED | PV_WARN_LAYERS_REJECTED | PV_WARN_SPARSE_LAYERS |
                                   PV_WARN_LARGE_TILT)) != 0 ||
                   m->board_warnings != 0 || m->dropped_events != 0;
  title(c, f, "RESULT", warn ? PV_COLOR_AMBER : PV_COLOR_GREEN, PV_COLOR_BLACK, usb_word(m));
  char num[32];
  const char *unit = "";
  volume_text(r->volume_cm3, units, num, sizeof num, &unit);
  char buf[64];
  if (r->interval_cm3 > 0) {
    char iv[32];
    const char *u2 = "";
    volume_text(r->interval_cm3, units, iv, sizeof iv, &u2);
    snprintf(buf, sizeof buf, PLUSMINUS " %s %s", iv, unit);
  } else {
    snprintf(buf, sizeof buf, "%s", unit);
  }
  int y = TITLE_H + 6;
  char one[96];
  snprintf(one, sizeof one, "%s %s", num, buf);
  if ((m->density.flags & PV_DENSITY_WET) && pv_text_width(&f->big, 1, one) <= c->width - 2 * MARGIN) {
    /* With a density: the volume on one line, so the density lines and
     * the quality flags still fit on 320 x 240. */
    pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, one);
    y += 34;
  } else {
    int scale = 2;
    if (pv_text_width(&f->big, 2, num) > c->width - 2 * MARGIN) scale = 1;
    pv_canvas_text(c, &f->big, scale, MARGIN, y, PV_COLOR_BLACK, num);
    y += (int)f->big.height_px * scale + 2;
    pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, buf);
    y += 34;
  }
  y = line(c, &f->body, y, PV_COLOR_BLACK, "depth %.1f mm  tilt %.0f" DEG, r->depth_mm, r->tilt_deg);
  y = density_lines(c, f, m, y);
  /* Quality flags from the core's table (pitvol.h): the ones that change
   * how far to trust the number first; then the notes, in grey. */
  const uint32_t attention = pv_warnings_attention(r->warnings, r->unseen_share);
  int shown = 0;
  const int room = (c->height - LINE_H - 4 - y) / LINE_H;
  if ((m->board_warnings & PV_BOARD_WARN_ENDED_UNPLUGGED) && shown++ < room) {
    y = line(c, &f->body, y, PV_COLOR_RED, "! ended while unplugged");
  }
  if (m->dropped_events != 0 && shown++ < room) {
    y = line(c, &f->body, y, PV_COLOR_RED, "! %u board events lost", (unsigned)m->dropped_events);
  }
  static const struct { uint32_t bit; pv_color_t ink; } order[] = {
      {PV_WARN_BRIDGED, PV_COLOR_RED},       {PV_WARN_LAYERS_REJECTED, PV_COLOR_AMBER},
      {PV_WARN_SPARSE_LAYERS, PV_COLOR_AMBER}, {PV_WARN_LARGE_TILT, PV_COLOR_AMBER},
      {PV_WARN_INVALID_POINTS, PV_COLOR_BLACK}, {PV_WARN_OUT_OF_RANGE, PV_COLOR_BLACK},
      {PV_WARN_POINTS_THINNED, PV_COLOR_BLACK},
  };
  for (size_t i = 0; i < sizeof order / sizeof order[0]; ++i) {
    if (!(attention & order[i].bit)) continue;
    if (shown++ < room) y = line(c, &f->body, y, order[i].ink, "! %s", pv_warning_short(order[i].bit));
  }
  if (shown == 0 && room > 0) {
    y = line(c, &f->body, y, PV_COLOR_GREEN, "no warnings");
    ++shown;
  }
  for (size_t i = 0; i < sizeof order / sizeof order[0]; ++i) {
    if (!(r->warnings & order[i].bit) || (attention & order[i].bit)) continue;
    if (shown++ < room) y = line(c, &f->body, y, PV_COLOR_GREY, "note: %s", pv_warning_short(order[i].bit));
  }
  pv_canvas_note(c, "result volume_cm3=%.17g interval_cm3=%.17g warnings=0x%x board_warnings=0x%x",
                 r->volume_cm3, r->interval_cm3, r->warnings, m->board_warnings);
  legend(c, f, "ENTER: done   START: new scan");
}

static void draw_refused(pv_canvas_t *c, const pv_board_model_t *m, const pv_board_fonts_t *f) {
  title(c, f, "REFUSED", PV_COLOR_RED, PV_COLOR_WHITE, usb_word(m));
  int y = TITLE_H + 8;
  pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, "no volume");
  y += 40;
  pv_advice_t a;
  pv_advice_refusal(&m->result, m->result_status, &a);
  y = line(c, &f->body, y, PV_COLOR_RED, "%s", a.why);
  y = line(c, &f->body, y + 4, PV_COLOR_BLACK, "%s", a.todo);
  if (m->board_warnings & PV_BOARD_WARN_ENDED_UNPLUGGED) {
    y = line(c, &f->body, y + 4, PV_COLOR_BLACK, "scan ended while unplugged");
  }
  if (m->dropped_events != 0) {
    y = line(c, &f->body, y + 4, PV_COLOR_RED, "%u board events lost", (unsigned)m->dropped_events);
  }
  char pts[32];
  pv_advice_grouped(m->result.points_in, pts, sizeof pts);
  line(c, &f->body, y + 4, PV_COLOR_GREY, "%s points", pts);
  pv_canvas_note(c, "refused status=%s", pv_status_name(m->result_status));
  legend(c, f, "ENTER: done   START: new scan");
}

void pv_board_draw(pv_canvas_t *c, const pv_board_model_t *m, const pv_board_fonts_t *f,
                   pv_board_units_t units) {
  pv_canvas_clear(c, PV_COLOR_WHITE);
  pv_canvas_note(c, "screen %s", pv_board_state_name(m->state));
  char num[32], pts[32];
  const char *unit = "";
  int y = TITLE_H + 12;
  switch (m->state) {
    case PV_BOARD_BOOT:
      title(c, f, "pitvol", PV_COLOR_BLACK, PV_COLOR_WHITE, NULL);
      y = line(c, &f->body, y, PV_COLOR_BLACK, "pit volume meter");
      line(c, &f->body, y, PV_COLOR_GREY, "version " PV_VERSION_STRING ", starting");
      break;
    case PV_BOARD_NO_SCANNER:
      title(c, f, "NO SCANNER", PV_COLOR_AMBER, PV_COLOR_BLACK, usb_word(m));
      pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, "plug it in");
      y += 44;
      if (m->armed) {
        y = line(c, &f->body, y, PV_COLOR_BLUE, "scan starts when plugged");
      } else {
        y = line(c, &f->body, y, PV_COLOR_BLACK, "USB cable to the scanner");
      }
      if (m->message[0] != '\0') line(c, &f->body, y + 4, PV_COLOR_RED, "%s", m->message);
      legend(c, f, m->armed ? "BACK: do not start" : "START: scan when plugged");
      break;
    case PV_BOARD_IDLE:
      title(c, f, "READY", PV_COLOR_BLACK, PV_COLOR_WHITE, usb_word(m));
      pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, "press START");
      y += 44;
      if (m->have_result && m->result_status == PV_OK) {
        volume_text(m->result.volume_cm3, units, num, sizeof num, &unit);
        y = line(c, &f->body, y, PV_COLOR_BLACK, "last: %s %s", num, unit);
      } else if (m->have_result) {
        y = line(c, &f->body, y, PV_COLOR_BLACK, "last: refused");
      }
      if (m->message[0] != '\0') line(c, &f->body, y + 4, PV_COLOR_RED, "%s", m->message);
      legend(c, f, m->have_result ? "START: scan   ENTER: last" : "START: scan");
      break;
    case PV_BOARD_SCANNING:
      draw_scanning(c, m, f, units);
      break;
    case PV_BOARD_PAUSED:
      title(c, f, "PAUSED", PV_COLOR_AMBER, PV_COLOR_BLACK, usb_word(m));
      pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, "scanner unplugged");
      y += 44;
      pv_advice_grouped(m->points, pts, sizeof pts);
      y = line(c, &f->body, y, PV_COLOR_BLACK, "%s points kept", pts);
      y = line(c, &f->body, y + 4, PV_COLOR_BLACK, "plug in: scan resumes");
      line(c, &f->body, y + 4, PV_COLOR_BLACK, "or STOP: measure them");
      legend(c, f, "STOP: end scan and measure");
      break;
    case PV_BOARD_MEASURING:
      title(c, f, "MEASURING", PV_COLOR_BLUE, PV_COLOR_WHITE, usb_word(m));
      pv_advice_grouped(m->points, pts, sizeof pts);
      pv_canvas_text(c, &f->big, 1, MARGIN, y, PV_COLOR_BLACK, "please wait");
      y += 44;
      line(c, &f->body, y, PV_COLOR_BLACK, "%s points", pts);
      break;
    case PV_BOARD_RESULT:
      draw_result(c, m, f, units);
      break;
    case PV_BOARD_REFUSED:
      draw_refused(c, m, f);
      break;
    case PV_BOARD_STATE_COUNT:
      break;
  }
}
