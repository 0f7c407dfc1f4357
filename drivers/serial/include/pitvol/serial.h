/*
 * Serial port driver: the board's UART (or a USB serial adapter, or a
 * pseudo-terminal in tests), raw 8N1, no flow control, non-blocking, for a
 * poll()-based event loop. One backend: POSIX termios (serial_termios.c).
 *
 *   pv_serial_t port;
 *   pv_serial_open(&port, "/dev/ttyS1", 115200);
 *   poll on pv_serial_fd(&port): POLLIN -> pv_serial_read, POLLOUT -> pv_serial_write
 */
#ifndef PITVOL_SERIAL_H
#define PITVOL_SERIAL_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pv_serial_status {
  /* 0, then 300 .. 399: PV_STATUS_BASE_SERIAL (pitvol/status_codes.h) */
  PV_SERIAL_OK = 0,
  PV_SERIAL_ERR_INVALID_ARGUMENT = 301, /* NULL, or not open */
  PV_SERIAL_ERR_OPEN = 302,             /* the device could not be opened (missing? permissions?) */
  PV_SERIAL_ERR_NOT_A_TTY = 303,        /* the path is not a terminal device */
  PV_SERIAL_ERR_BAUD = 304,             /* the baud rate is not one termios offers */
  PV_SERIAL_ERR_CONFIG = 305,           /* the port refused raw 8N1 settings */
  PV_SERIAL_ERR_IO = 306,               /* a read or write failed */
  PV_SERIAL_HANGUP = 307                /* the other side went away (cable, pty closed) */
} pv_serial_status_t;

const char *pv_serial_status_name(pv_serial_status_t status);
/* What went wrong and what the user can do. Never NULL. */
const char *pv_serial_status_message(pv_serial_status_t status);

typedef struct pv_serial {
  int fd;          /* -1 when closed */
  uint32_t baud;
  int last_errno;  /* of the last error */
} pv_serial_t;

/* 1 if the rate is supported (9600 .. 4000000 standard rates). */
int pv_serial_baud_supported(uint32_t baud);

/* Opens path, sets raw 8N1 at baud, no flow control, non-blocking, and
 * discards bytes that were waiting from before. */
PV_NODISCARD pv_serial_status_t pv_serial_open(pv_serial_t *port, const char *path, uint32_t baud);
/* Takes over an open terminal fd (e.g. from openpty) and configures it the
 * same way; the port closes it. */
PV_NODISCARD pv_serial_status_t pv_serial_adopt(pv_serial_t *port, int fd, uint32_t baud);
void pv_serial_close(pv_serial_t *port);

/* The fd to poll. */
int pv_serial_fd(const pv_serial_t *port);

/* Never blocks. *got / *written: bytes moved, 0 if none would move now. */
PV_NODISCARD pv_serial_status_t pv_serial_read(pv_serial_t *port, void *buf, size_t cap,
                                               size_t *got);
PV_NODISCARD pv_serial_status_t pv_serial_write(pv_serial_t *port, const void *data, size_t len,
                                                size_t *written);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_SERIAL_H */
