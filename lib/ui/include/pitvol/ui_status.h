/*
 * What the parsers of what a user types return (user_input.h,
 * config_fields.h): 0, or a code of 801 .. 849 (PV_STATUS_BASE_UI,
 * pitvol/status_codes.h). The err sentence beside it names the value, the
 * key and the allowed range; the message says what kind of fault it is.
 */
#ifndef PITVOL_UI_STATUS_H
#define PITVOL_UI_STATUS_H

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pv_ui_status {
  PV_UI_OK = 0,
  PV_UI_ERR_INVALID_ARGUMENT = 801, /* NULL, or a kind that is not a pv_input_kind_t */
  PV_UI_ERR_NUMBER_MISSING = 802,   /* empty text where a number belongs */
  PV_UI_ERR_DECIMAL_COMMA = 803,    /* "1,5": a decimal comma */
  PV_UI_ERR_NOT_A_NUMBER = 804,     /* not a decimal number (hex, inf, nan, words) */
  PV_UI_ERR_OVERFLOW = 805,         /* beyond what a double holds (1e999) */
  PV_UI_ERR_OUT_OF_RANGE = 806,     /* a number outside its plausible or allowed range */
  PV_UI_ERR_NOT_WHOLE = 807,        /* a fraction where a whole number belongs */
  PV_UI_ERR_TOO_LONG = 808,         /* text longer than its field */
  PV_UI_ERR_CONTROL_CHAR = 809,     /* text with a control character */
  PV_UI_ERR_UNKNOWN_SETTING = 810,  /* a setting name the core does not have */
  PV_UI_ERR_UNKNOWN_METHOD = 811    /* method = something other than surface, paper, polar */
} pv_ui_status_t;

/* The symbol ("PV_UI_ERR_DECIMAL_COMMA"). Never NULL. */
const char *pv_ui_status_name(pv_ui_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_ui_status_message(pv_ui_status_t status);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_UI_STATUS_H */
