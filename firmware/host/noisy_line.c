/* A serial line with noise between two pseudo-terminals (noisy_line.h). */
#include "noisy_line.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <stdio.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

#include "pitvol/splitmix64.h"


/* Copies what can be read from `from` to `to`, with noise. */
static void relay(pv_noisy_line_t *l, int from, int to) {
  uint8_t in[256], out[512];
  const ssize_t n = read(from, in, sizeof in);
  if (n <= 0) return;
  size_t o = 0;
  for (ssize_t i = 0; i < n; ++i) {
    l->bytes++;
    if (l->p > 0 && pv_splitmix64_unit(&l->rng) < l->p) {
      l->hit++;
      switch (pv_splitmix64_next(&l->rng) % 3u) {
        case 0: out[o++] = (uint8_t)(in[i] ^ (1u << (pv_splitmix64_next(&l->rng) % 8u))); break;
        case 1: break; /* dropped */
        default: out[o++] = (uint8_t)pv_splitmix64_next(&l->rng); out[o++] = in[i]; break;
      }
    } else {
      out[o++] = in[i];
    }
  }
  /* Non-blocking: what the far side has no room for is lost, as on a wire. */
  if (o > 0 && write(to, out, o) < 0 && errno != EAGAIN) return;
}

static void *run(void *arg) {
  pv_noisy_line_t *l = (pv_noisy_line_t *)arg;
  while (!l->stop) {
    struct pollfd p[2] = {{l->board_master, POLLIN, 0}, {l->host_master, POLLIN, 0}};
    if (poll(p, 2, 50) <= 0) continue;
    if ((p[0].revents | p[1].revents) & POLLHUP) usleep(10000); /* a side closed: do not spin */
    if (p[0].revents & POLLIN) relay(l, l->board_master, l->host_master);
    if (p[1].revents & POLLIN) relay(l, l->host_master, l->board_master);
  }
  return NULL;
}

static int raw(int fd) {
  struct termios t;
  if (tcgetattr(fd, &t) != 0) return -1;
  cfmakeraw(&t);
  return tcsetattr(fd, TCSANOW, &t);
}

int pv_noisy_line_open(pv_noisy_line_t *l, const char *link, double percent, uint64_t seed, char *err,
                       size_t errcap) {
  memset(l, 0, sizeof *l);
  l->board_fd = l->board_master = l->host_master = l->host_slave = -1;
  l->p = percent / 100.0;
  l->rng = seed;
  char name[256];
  if (openpty(&l->board_master, &l->board_fd, name, NULL, NULL) != 0 ||
      snprintf(l->board_name, sizeof l->board_name, "%s", name) >= (int)sizeof l->board_name ||
      openpty(&l->host_master, &l->host_slave, name, NULL, NULL) != 0) {
    snprintf(err, errcap, "openpty: %s", strerror(errno));
    return -1;
  }
  /* Raw before anyone uses them: a cooked slave would echo frames back. */
  if (raw(l->board_fd) != 0 || raw(l->host_slave) != 0 ||
      fcntl(l->board_master, F_SETFL, O_NONBLOCK) != 0 || fcntl(l->host_master, F_SETFL, O_NONBLOCK) != 0) {
    snprintf(err, errcap, "pty setup: %s", strerror(errno));
    return -1;
  }
  unlink(link);
  if (symlink(name, link) != 0) {
    snprintf(err, errcap, "%s: %s", link, strerror(errno));
    return -1;
  }
  if (pthread_create(&l->thread, NULL, run, l) != 0) {
    snprintf(err, errcap, "cannot start the line's thread");
    return -1;
  }
  l->running = 1;
  return 0;
}

void pv_noisy_line_close(pv_noisy_line_t *l) {
  if (l->running) {
    l->stop = 1;
    pthread_join(l->thread, NULL);
  }
  if (l->board_master >= 0) close(l->board_master);
  if (l->host_master >= 0) close(l->host_master);
  if (l->host_slave >= 0) close(l->host_slave);
  l->running = 0;
  l->board_master = l->host_master = l->host_slave = -1;
}
