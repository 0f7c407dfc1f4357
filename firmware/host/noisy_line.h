/*
 * A serial line with noise, for host tests of the board's link: two
 * pseudo-terminals joined by a thread that copies bytes both ways and, at
 * a given share of the bytes, flips a bit, drops the byte or puts a random
 * byte before it (the noise of the line-noise test). The board
 * gets one side (board_fd, a terminal), LINK names the other side for
 * pitvol-monitor. A side nobody reads loses what is sent to it once its
 * buffer is full, as a UART without a receiver does.
 */
#ifndef PV_NOISY_LINE_H
#define PV_NOISY_LINE_H

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>

typedef struct pv_noisy_line {
  int board_fd;              /* slave of the board's pty: give it to the board */
  char board_name[64];       /* its path, for a board that opens the port by name */
  int board_master, host_master, host_slave;
  double p;                  /* share of bytes hit, 0 .. 1 */
  uint64_t rng;
  volatile int stop;
  pthread_t thread;
  int running;
  unsigned long bytes, hit;  /* bytes copied, bytes hit by noise */
} pv_noisy_line_t;

/* 0, or -1 with a sentence in err. percent 0: a clean line. */
int pv_noisy_line_open(pv_noisy_line_t *l, const char *link, double percent, uint64_t seed, char *err,
                       size_t errcap);
/* Stops the thread, closes the host side (not board_fd: the board owns it). */
void pv_noisy_line_close(pv_noisy_line_t *l);

#endif
