// pitvol-monitor's end of the serial link (see host_link.h).
#include "host_link.h"

#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <cstring>

namespace pv::monitor {

namespace {

using Clock = std::chrono::steady_clock;

long write_port(void *ctx, const uint8_t *data, size_t len) {
  size_t written = 0;
  const pv_serial_status_t st = pv_serial_write(static_cast<pv_serial_t *>(ctx), data, len, &written);
  return st == PV_SERIAL_OK ? long(written) : -1;
}

int ms_left(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? int(left) : 0;
}

// A starting sequence number unlike the previous monitor's (see pv_link_init).
uint32_t random_seq() {
  const auto t = uint64_t(Clock::now().time_since_epoch().count());
  uint64_t z = t ^ (uint64_t(getpid()) << 32);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return uint32_t(z ^ (z >> 31));
}

}  // namespace

HostLink::HostLink() : link_(new pv_link_t) { pv_link_init(link_.get(), random_seq()); }

HostLink::~HostLink() { pv_serial_close(&port_); }

bool HostLink::open(const std::string &port, uint32_t baud, std::string *err) {
  const pv_serial_status_t st = pv_serial_open(&port_, port.c_str(), baud);
  if (st == PV_SERIAL_OK) return true;
  *err = port + ": " + pv_serial_status_message(st);
  if (port_.last_errno) *err += std::string(" (") + std::strerror(port_.last_errno) + ")";
  return false;
}

const pv_link_stats_t &HostLink::stats() const { return link_->stats; }

bool HostLink::post(const pitvol_Message &msg, uint32_t *seq, std::string *err) {
  const pv_link_status_t st = pv_link_send(link_.get(), &msg, PV_LINK_RELIABLE, seq);
  if (st == PV_LINK_OK) return true;
  *err = pv_link_status_message(st);
  return false;
}

bool HostLink::post_again(const pitvol_Message &cmd, uint32_t seq, std::string *err) {
  const pv_link_status_t st = pv_link_send_again(link_.get(), &cmd, seq);
  if (st == PV_LINK_OK) return true;
  *err = pv_link_status_message(st);
  return false;
}

bool HostLink::pump(int timeout_ms, const Handler &on_msg, std::string *err, int extra_fd,
                    bool *extra_ready) {
  pollfd fds[2] = {
      {pv_serial_fd(&port_), short(POLLIN | (pv_link_tx_pending(link_.get()) ? POLLOUT : 0)), 0},
      {extra_fd, POLLIN, 0}};
  if (extra_ready) *extra_ready = false;
  const int n = poll(fds, extra_fd >= 0 ? 2 : 1, timeout_ms);
  if (n <= 0) return true;  // timeout, or EINTR: the caller loops
  if (extra_ready && extra_fd >= 0 && (fds[1].revents & (POLLIN | POLLHUP))) *extra_ready = true;
  pollfd &pfd = fds[0];
  if (pfd.revents & POLLOUT) {
    if (pv_link_tx_flush(link_.get(), write_port, &port_) != PV_LINK_OK) {
      *err = pv_serial_status_message(PV_SERIAL_ERR_IO);
      return false;
    }
  }
  if (pfd.revents & (POLLIN | POLLHUP | POLLERR)) {
    uint8_t buf[512];
    size_t got = 0;
    const pv_serial_status_t st = pv_serial_read(&port_, buf, sizeof buf, &got);
    if (st != PV_SERIAL_OK) {
      *err = pv_serial_status_message(st);
      return false;
    }
    for (size_t at = 0; at < got;) {
      pv_link_rx_t rx;
      int have = 0;
      at += pv_link_feed(link_.get(), buf + at, got - at, &rx, &have);
      if (have) on_msg(rx);
    }
  }
  return true;
}

HostLink::Reply HostLink::command(const pitvol_Message &cmd, pv_link_rx_t *reply,
                                  const Handler &on_msg, int retry_ms, int tries,
                                  std::string *err) {
  uint32_t seq = 0;
  if (!post(cmd, &seq, err)) return Reply::PortError;
  bool answered = false;
  Reply result = Reply::Timeout;
  const Handler watch = [&](const pv_link_rx_t &rx) {
    const pitvol_Message &m = rx.msg;
    if (m.which_body == pitvol_Message_ack_tag && m.body.ack.command_seq == seq) {
      answered = true;
      result = Reply::Ack;
      *reply = rx;
    } else if (m.which_body == pitvol_Message_nack_tag && m.body.nack.command_seq == seq) {
      answered = true;
      result = Reply::Nack;
      *reply = rx;
    } else {
      on_msg(rx);
    }
  };
  for (int attempt = 0; attempt < tries && !answered; ++attempt) {
    if (attempt > 0 && pv_link_send_again(link_.get(), &cmd, seq) != PV_LINK_OK) {
      *err = "the send queue is full; the board does not read";
      return Reply::PortError;
    }
    const auto deadline = Clock::now() + std::chrono::milliseconds(retry_ms);
    while (!answered) {
      const int left = ms_left(deadline);
      if (left == 0) break;
      if (!pump(left, watch, err)) return Reply::PortError;
    }
  }
  // Whatever is still queued goes out before we return.
  for (int i = 0; i < 50 && pv_link_tx_pending(link_.get()); ++i) pump(10, on_msg, err);
  if (!answered) *err = "the board did not answer; check the cable, the port and the baud rate";
  return result;
}

}  // namespace pv::monitor
