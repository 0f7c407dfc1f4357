/*
 * The board application: everything sized and allocated once at start
 * (core block, canvas, display and input backends, USB transfers), then one
 * event loop on poll() over the libusb descriptors, the buttons, a timerfd
 * (live estimate) and a signalfd (SIGTERM/SIGINT end the loop), plus any
 * descriptor added with pv_board_app_watch().
 *
 * Hook for the serial link (lib/link/, firmware/board_link.c): open the port after
 * pv_board_app_init, register its fd with pv_board_app_watch(); in the
 * callback, decode commands and feed them in with pv_board_app_post()
 * (PV_EV_START_STOP, ...); register pv_board_app_set_observer() to hear of
 * every state change, live estimate and result to send out.
 */
#ifndef PV_BOARD_APP_H
#define PV_BOARD_APP_H

#include <poll.h>
#include <stddef.h>

#include "board_config.h"
#include "board_screens.h"
#include "board_state.h"
#include "pitvol/display.h"
#include "pitvol/input.h"
#include "pitvol/usb_scanner.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_BOARD_MAX_WATCHES 4u
#define PV_BOARD_EVENT_QUEUE 32u
#define PV_BOARD_TEXT_LOG_BYTES 4096u

typedef struct pv_board_app pv_board_app_t;

/* Called from the loop when fd has revents. */
typedef void (*pv_board_watch_fn)(pv_board_app_t *app, int fd, short revents, void *user);

typedef enum pv_board_news {
  PV_NEWS_STATE = 0,   /* model.state changed */
  PV_NEWS_ESTIMATE = 1,/* model.live updated */
  PV_NEWS_RESULT = 2   /* model.result is final (RESULT or REFUSED) */
} pv_board_news_t;
typedef void (*pv_board_observer_fn)(pv_board_app_t *app, pv_board_news_t what,
                                     const pv_board_model_t *m, void *user);

struct pv_board_app {
  pv_board_config_t cfg;
  pv_board_model_t model;
  pv_board_fonts_t fonts;
  void *block;
  pv_session_t *session;
  pv_usb_scanner_t *usb;
  pv_usb_state_t usb_state;
  pv_display_t *display;
  pv_canvas_t canvas;
  void *canvas_mem;
  pv_input_t *input;
  int timer_fd, signal_fd;
  struct pollfd fds[PV_USB_MAX_POLLFDS + 3 + PV_BOARD_MAX_WATCHES];
  struct {
    int fd;
    short events;
    pv_board_watch_fn fn;
    void *user;
  } watches[PV_BOARD_MAX_WATCHES];
  size_t nwatches;
  pv_board_event_t queue[PV_BOARD_EVENT_QUEUE];
  size_t q_head, q_len;
  uint64_t scan_mark_ms;   /* when scan_ms was last advanced */
  uint64_t next_estimate_ms; /* no live estimate before (duty <= 50 %) */
  int dirty;
  int measure_pending;
  int quit;
  pv_board_state_t last_shown; /* state of the last screen presented */
  pv_board_observer_fn observer;
  void *observer_user;
  unsigned long presents;
};

/* 0, then 951 .. 999: PV_STATUS_BASE_BOARD_APP (pitvol/status_codes.h).
 * The start's faults name the part that failed; err says which device or
 * setting and ends in the failing module's own status name. */
typedef enum pv_board_app_status {
  PV_BOARD_APP_OK = 0,
  PV_BOARD_APP_ERR_QUEUE_FULL = 951,     /* the event queue is full: the event was dropped */
  PV_BOARD_APP_ERR_WATCHES_FULL = 952,   /* all PV_BOARD_MAX_WATCHES slots are taken */
  PV_BOARD_APP_ERR_WATCH_ARGUMENT = 953, /* a watch without a descriptor or a callback */
  PV_BOARD_APP_ERR_NOT_WATCHED = 954,    /* the descriptor is not watched */
  PV_BOARD_APP_ERR_CONFIG = 955,         /* the configuration does not pass its check */
  PV_BOARD_APP_ERR_DISPLAY = 956,        /* fonts, canvas or display */
  PV_BOARD_APP_ERR_CORE = 957,           /* the core's block cannot be set up */
  PV_BOARD_APP_ERR_INPUT = 958,          /* the buttons */
  PV_BOARD_APP_ERR_TIMER = 959,          /* the live estimate's timer */
  PV_BOARD_APP_ERR_SIGNAL = 960,         /* the signalfd for SIGTERM/SIGINT */
  PV_BOARD_APP_ERR_USB = 961,            /* the scanner's USB driver */
  PV_BOARD_APP_ERR_POLL = 962            /* the event loop's poll() failed */
} pv_board_app_status_t;

/* The symbol ("PV_BOARD_APP_ERR_QUEUE_FULL"). Never NULL. */
const char *pv_board_app_status_name(pv_board_app_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_board_app_status_message(pv_board_app_status_t status);

/* Sets up everything from the configuration. PV_BOARD_APP_OK, or the part
 * that failed (_CONFIG, _DISPLAY, _CORE, _INPUT, _TIMER, _SIGNAL, _USB) with
 * a sentence in err (what failed, what to do, "[STATUS_NAME]"). */
PV_NODISCARD pv_board_app_status_t pv_board_app_init(pv_board_app_t *app,
                                                     const pv_board_config_t *cfg, char *err,
                                                     size_t errcap);
/* Runs until SIGTERM/SIGINT or pv_board_app_quit. PV_BOARD_APP_OK, or
 * PV_BOARD_APP_ERR_POLL with a sentence in err (the loop cannot wait). */
PV_NODISCARD pv_board_app_status_t pv_board_app_run(pv_board_app_t *app, char *err, size_t errcap);
void pv_board_app_quit(pv_board_app_t *app);
void pv_board_app_close(pv_board_app_t *app);

/* Extra descriptors (the serial link). PV_BOARD_APP_OK,
 * PV_BOARD_APP_ERR_WATCHES_FULL or PV_BOARD_APP_ERR_WATCH_ARGUMENT. */
PV_NODISCARD pv_board_app_status_t pv_board_app_watch(pv_board_app_t *app, int fd, short events,
                                                      pv_board_watch_fn fn, void *user);
/* Changes what a watched fd waits for (e.g. POLLIN | POLLOUT while the
 * link has bytes to send). PV_BOARD_APP_OK, or PV_BOARD_APP_ERR_NOT_WATCHED. */
PV_NODISCARD pv_board_app_status_t pv_board_app_watch_events(pv_board_app_t *app, int fd,
                                                             short events);
/* Queues an event (from a watch callback). PV_BOARD_APP_OK, or
 * PV_BOARD_APP_ERR_QUEUE_FULL: the event is then counted in
 * model.dropped_events (the result screens show it) and logged; the caller
 * says so to whoever sent it. */
PV_NODISCARD pv_board_app_status_t pv_board_app_post(pv_board_app_t *app, pv_board_event_t ev);
void pv_board_app_set_observer(pv_board_app_t *app, pv_board_observer_fn fn, void *user);

#ifdef __cplusplus
}
#endif
#endif
