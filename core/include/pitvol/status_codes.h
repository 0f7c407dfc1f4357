/*
 * How the C modules report failure (docs/errors.md).
 *
 * A function whose caller acts on the cause returns its module's status
 * enum: 0 is success in every module, every other value lies in the
 * module's range below, so a number in a log names its module. Each enum
 * has a name function (the symbol) and a message function (what went wrong
 * and what to do). Where the particulars matter to the user (a path, a
 * line of a file, the system's reason) the function also writes them into
 * its err argument, one sentence.
 *
 * Header only and free of dependencies: the core and every module above it
 * include it.
 */
#ifndef PITVOL_STATUS_CODES_H
#define PITVOL_STATUS_CODES_H

/* For functions that can fail: a caller that drops the status does not
 * compile (pv_strict's -Werror=unused-result). C++ may drop one on purpose
 * with a (void) cast; GCC's C attribute ignores that cast, so C code keeps
 * the status in a variable and says why it is not acted on. */
#if defined(__cplusplus) && __cplusplus >= 201703L
#define PV_NODISCARD [[nodiscard]]
#elif defined(__GNUC__) || defined(__clang__)
#define PV_NODISCARD __attribute__((warn_unused_result))
#else
#define PV_NODISCARD
#endif

/* First code of each module's range of PV_STATUS_RANGE codes. The core's
 * and the board's codes travel on the serial link (Result.status,
 * Error.code: docs/protocol/serial.md) and never change. */
#define PV_STATUS_RANGE 100
#define PV_STATUS_BASE_CORE 0      /* pv_status_t (pitvol.h) */
#define PV_STATUS_BASE_BOARD 100   /* the board's faults on the link (Error.code) */
#define PV_STATUS_BASE_USB 200     /* pv_usb_status_t; pv_usb_parse_t from 251 */
#define PV_STATUS_BASE_SERIAL 300  /* pv_serial_status_t */
#define PV_STATUS_BASE_LOG 400     /* pv_log_status_t */
#define PV_STATUS_BASE_LINK 500    /* pv_link_status_t */
#define PV_STATUS_BASE_DENSITY 600 /* pv_density_status_t */
/* The board's own modules, 50 codes each. */
#define PV_STATUS_BASE_DISPLAY 700      /* pv_display_status_t (drivers/display) */
#define PV_STATUS_BASE_INPUT 750        /* pv_input_status_t (drivers/input, the buttons) */
#define PV_STATUS_BASE_UI 800           /* pv_ui_status_t (lib/ui: typed numbers, settings) */
#define PV_STATUS_BASE_BOARD_CONFIG 850 /* pv_board_config_status_t (firmware) */
#define PV_STATUS_BASE_WATCHDOG 900     /* pv_board_watchdog_status_t (firmware) */
#define PV_STATUS_BASE_BOARD_APP 950    /* pv_board_app_status_t (firmware: start, loop, queue) */
#define PV_STATUS_BASE_BOARD_LINK 1000  /* pv_board_link_status_t (firmware: the link's start) */
#define PV_STATUS_BASE_END 1050         /* the first code no module has */

#endif /* PITVOL_STATUS_CODES_H */
