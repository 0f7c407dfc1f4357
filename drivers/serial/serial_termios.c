/* Serial port driver on POSIX termios (see pitvol/serial.h). */
#define _DEFAULT_SOURCE
#include "pitvol/serial.h"

#include <errno.h>
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

_Static_assert(PV_SERIAL_ERR_INVALID_ARGUMENT > PV_STATUS_BASE_SERIAL &&
                   PV_SERIAL_HANGUP < PV_STATUS_BASE_SERIAL + PV_STATUS_RANGE,
               "pv_serial_status_t in its range (pitvol/status_codes.h)");

const char *pv_serial_status_name(pv_serial_status_t status) {
  switch (status) {
    case PV_SERIAL_OK: return "PV_SERIAL_OK";
    case PV_SERIAL_ERR_INVALID_ARGUMENT: return "PV_SERIAL_ERR_INVALID_ARGUMENT";
    case PV_SERIAL_ERR_OPEN: return "PV_SERIAL_ERR_OPEN";
    case PV_SERIAL_ERR_NOT_A_TTY: return "PV_SERIAL_ERR_NOT_A_TTY";
    case PV_SERIAL_ERR_BAUD: return "PV_SERIAL_ERR_BAUD";
    case PV_SERIAL_ERR_CONFIG: return "PV_SERIAL_ERR_CONFIG";
    case PV_SERIAL_ERR_IO: return "PV_SERIAL_ERR_IO";
    case PV_SERIAL_HANGUP: return "PV_SERIAL_HANGUP";
  }
  return "PV_SERIAL_ERR_UNKNOWN";
}

const char *pv_serial_status_message(pv_serial_status_t status) {
  switch (status) {
    case PV_SERIAL_OK: return "ok";
    case PV_SERIAL_ERR_INVALID_ARGUMENT: return "the serial port is not open; a caller bug";
    case PV_SERIAL_ERR_OPEN:
      return "the serial port could not be opened; check the device name, that it is "
             "plugged in, and that you may use it (group dialout)";
    case PV_SERIAL_ERR_NOT_A_TTY:
      return "that path is not a serial port; give the device, e.g. /dev/ttyUSB0";
    case PV_SERIAL_ERR_BAUD:
      return "that baud rate is not supported; use a standard rate such as 115200";
    case PV_SERIAL_ERR_CONFIG:
      return "the serial port refused its settings (raw 8N1); check the device";
    case PV_SERIAL_ERR_IO:
      return "reading or writing the serial port failed; check the cable and the port";
    case PV_SERIAL_HANGUP:
      return "the other end of the serial line went away; reconnect the cable or restart "
             "the program on the other side";
  }
  return "unknown serial status";
}

static speed_t speed_of(uint32_t baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 500000: return B500000;
    case 921600: return B921600;
    case 1000000: return B1000000;
    case 1500000: return B1500000;
    case 2000000: return B2000000;
    case 3000000: return B3000000;
    case 4000000: return B4000000;
    default: return B0;
  }
}

int pv_serial_baud_supported(uint32_t baud) { return speed_of(baud) != B0; }

static pv_serial_status_t fail(pv_serial_t *port, pv_serial_status_t st) {
  port->last_errno = errno;
  return st;
}

pv_serial_status_t pv_serial_adopt(pv_serial_t *port, int fd, uint32_t baud) {
  if (!port || fd < 0) return PV_SERIAL_ERR_INVALID_ARGUMENT;
  port->fd = -1;
  port->baud = baud;
  port->last_errno = 0;
  const speed_t speed = speed_of(baud);
  if (speed == B0) return PV_SERIAL_ERR_BAUD;
  if (!isatty(fd)) return fail(port, PV_SERIAL_ERR_NOT_A_TTY);
  struct termios t;
  if (tcgetattr(fd, &t) != 0) return fail(port, PV_SERIAL_ERR_CONFIG);
  cfmakeraw(&t);                /* 8 bits, no parity, no echo, no line editing */
  t.c_cflag &= ~(tcflag_t)(CSTOPB | CRTSCTS);
  t.c_cflag |= CLOCAL | CREAD;  /* ignore modem lines, enable the receiver */
  t.c_iflag &= ~(tcflag_t)(IXON | IXOFF | IXANY);
  /* With O_NONBLOCK, VMIN 1 makes an empty read EAGAIN, so a read of 0
   * bytes means a hangup (VMIN 0 would return 0 for "nothing yet"). */
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0 ||
      tcsetattr(fd, TCSANOW, &t) != 0)
    return fail(port, PV_SERIAL_ERR_CONFIG);
  const int flags = fcntl(fd, F_GETFL);
  if (flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0)
    return fail(port, PV_SERIAL_ERR_CONFIG);
  /* Bytes that arrived before we opened belong to nobody: drop them. */
  (void)tcflush(fd, TCIOFLUSH);
  port->fd = fd;
  return PV_SERIAL_OK;
}

pv_serial_status_t pv_serial_open(pv_serial_t *port, const char *path, uint32_t baud) {
  if (!port || !path) return PV_SERIAL_ERR_INVALID_ARGUMENT;
  port->fd = -1;
  if (!pv_serial_baud_supported(baud)) return PV_SERIAL_ERR_BAUD;
  const int fd = open(path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return fail(port, PV_SERIAL_ERR_OPEN);
  const pv_serial_status_t st = pv_serial_adopt(port, fd, baud);
  if (st != PV_SERIAL_OK) {
    const int e = port->last_errno;
    close(fd);
    port->last_errno = e;
  }
  return st;
}

void pv_serial_close(pv_serial_t *port) {
  if (!port || port->fd < 0) return;
  close(port->fd);
  port->fd = -1;
}

int pv_serial_fd(const pv_serial_t *port) { return port ? port->fd : -1; }

pv_serial_status_t pv_serial_read(pv_serial_t *port, void *buf, size_t cap, size_t *got) {
  if (got) *got = 0;
  if (!port || port->fd < 0 || !buf || !got) return PV_SERIAL_ERR_INVALID_ARGUMENT;
  for (;;) {
    const ssize_t r = read(port->fd, buf, cap);
    if (r > 0) {
      *got = (size_t)r;
      return PV_SERIAL_OK;
    }
    if (r == 0) return cap ? PV_SERIAL_HANGUP : PV_SERIAL_OK;
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return PV_SERIAL_OK;
    /* A pty whose other side closed reads EIO on Linux. */
    return fail(port, errno == EIO ? PV_SERIAL_HANGUP : PV_SERIAL_ERR_IO);
  }
}

pv_serial_status_t pv_serial_write(pv_serial_t *port, const void *data, size_t len,
                                   size_t *written) {
  if (written) *written = 0;
  if (!port || port->fd < 0 || (!data && len) || !written) return PV_SERIAL_ERR_INVALID_ARGUMENT;
  for (;;) {
    const ssize_t r = write(port->fd, data, len);
    if (r >= 0) {
      *written = (size_t)r;
      return PV_SERIAL_OK;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return PV_SERIAL_OK;
    return fail(port, errno == EIO ? PV_SERIAL_HANGUP : PV_SERIAL_ERR_IO);
  }
}
