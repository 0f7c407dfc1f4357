#include "board_watchdog.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <sys/un.h>
#include <unistd.h>

_Static_assert(PV_BOARD_WATCHDOG_ERR_SOCKET_PATH > PV_STATUS_BASE_WATCHDOG &&
                   PV_BOARD_WATCHDOG_ERR_TIMER < PV_STATUS_BASE_BOARD_APP,
               "pv_board_watchdog_status_t in its range (pitvol/status_codes.h)");

const char *pv_board_watchdog_status_name(pv_board_watchdog_status_t status) {
  switch (status) {
    case PV_BOARD_WATCHDOG_OK: return "PV_BOARD_WATCHDOG_OK";
    case PV_BOARD_WATCHDOG_ERR_SOCKET_PATH: return "PV_BOARD_WATCHDOG_ERR_SOCKET_PATH";
    case PV_BOARD_WATCHDOG_ERR_NOTIFY: return "PV_BOARD_WATCHDOG_ERR_NOTIFY";
    case PV_BOARD_WATCHDOG_ERR_TIMER: return "PV_BOARD_WATCHDOG_ERR_TIMER";
  }
  return "PV_BOARD_WATCHDOG_ERR_UNKNOWN";
}

const char *pv_board_watchdog_status_message(pv_board_watchdog_status_t status) {
  switch (status) {
    case PV_BOARD_WATCHDOG_OK: return "started";
    case PV_BOARD_WATCHDOG_ERR_SOCKET_PATH:
      return "NOTIFY_SOCKET is not a socket path; run the board from its systemd unit "
             "(packaging/pitvol-board.service) or unset NOTIFY_SOCKET";
    case PV_BOARD_WATCHDOG_ERR_NOTIFY:
      return "systemd's notify socket does not take READY=1; check that the unit is "
             "Type=notify and systemd is running";
    case PV_BOARD_WATCHDOG_ERR_TIMER:
      return "the watchdog's ping timer cannot be set up; free descriptors or remove "
             "WatchdogSec= from the unit";
  }
  return "unknown watchdog status";
}

static int g_sock = -1;
static int g_timer = -1;
static struct sockaddr_un g_addr;
static socklen_t g_addr_len;
static unsigned long g_pings;

static int notify(const char *msg) {
  return sendto(g_sock, msg, strlen(msg), MSG_NOSIGNAL, (const struct sockaddr *)&g_addr,
                g_addr_len) < 0 ? -1 : 0;
}

static void on_timer(pv_board_app_t *app, int fd, short revents, void *user) {
  (void)app, (void)revents, (void)user;
  unsigned long long expirations = 0;
  if (read(fd, &expirations, sizeof expirations) != (ssize_t)sizeof expirations) return;
  /* A failed ping is not fatal: systemd restarts the board if they stop. */
  if (notify("WATCHDOG=1") == 0) ++g_pings;
}

pv_board_watchdog_status_t pv_board_watchdog_start(pv_board_app_t *app, char *err,
                                                   size_t errcap) {
  const char *path = getenv("NOTIFY_SOCKET");
  if (path == NULL || path[0] == '\0') return PV_BOARD_WATCHDOG_OK;
  const size_t len = strlen(path);
  if ((path[0] != '/' && path[0] != '@') || len >= sizeof g_addr.sun_path) {
    snprintf(err, errcap, "systemd: NOTIFY_SOCKET '%s' is not a socket path", path);
    return PV_BOARD_WATCHDOG_ERR_SOCKET_PATH;
  }
  memset(&g_addr, 0, sizeof g_addr);
  g_addr.sun_family = AF_UNIX;
  memcpy(g_addr.sun_path, path, len);
  if (path[0] == '@') g_addr.sun_path[0] = '\0'; /* the abstract namespace */
  g_addr_len = (socklen_t)(offsetof(struct sockaddr_un, sun_path) + len);
  g_sock = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (g_sock < 0 || notify("READY=1") != 0) {
    snprintf(err, errcap, "systemd: cannot notify %s (%s)", path, strerror(errno));
    return PV_BOARD_WATCHDOG_ERR_NOTIFY;
  }

  const char *usec = getenv("WATCHDOG_USEC");
  const char *pid = getenv("WATCHDOG_PID");
  char *end = NULL;
  const unsigned long long period_us = usec != NULL ? strtoull(usec, &end, 10) : 0;
  if (period_us == 0 || end == NULL || *end != '\0') return PV_BOARD_WATCHDOG_OK; /* none asked */
  if (pid != NULL && strtol(pid, NULL, 10) != (long)getpid()) {
    return PV_BOARD_WATCHDOG_OK; /* meant for another process */
  }
  const unsigned long long half_us = period_us / 2 > 0 ? period_us / 2 : 1;
  const struct itimerspec every = {
      {(time_t)(half_us / 1000000u), (long)(half_us % 1000000u) * 1000L},
      {(time_t)(half_us / 1000000u), (long)(half_us % 1000000u) * 1000L}};
  g_timer = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (g_timer < 0 || timerfd_settime(g_timer, 0, &every, NULL) != 0) {
    snprintf(err, errcap, "systemd: cannot set up the watchdog timer (%s)", strerror(errno));
    return PV_BOARD_WATCHDOG_ERR_TIMER;
  }
  const pv_board_app_status_t wst = pv_board_app_watch(app, g_timer, POLLIN, on_timer, NULL);
  if (wst != PV_BOARD_APP_OK) {
    snprintf(err, errcap, "systemd: the watchdog timer is not watched: %s [%s]",
             pv_board_app_status_message(wst), pv_board_app_status_name(wst));
    return PV_BOARD_WATCHDOG_ERR_TIMER;
  }
  printf("pitvol-board: systemd watchdog, a ping every %llu ms\n", half_us / 1000u);
  return PV_BOARD_WATCHDOG_OK;
}

void pv_board_watchdog_stop(void) {
  if (g_timer >= 0) {
    close(g_timer);
    printf("pitvol-board: systemd watchdog: %lu pings\n", g_pings);
  }
  if (g_sock >= 0) close(g_sock);
  g_timer = g_sock = -1;
}
