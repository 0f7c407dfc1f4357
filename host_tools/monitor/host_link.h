// pitvol-monitor's end of the serial link: the board's own link layer
// (lib/link) and serial driver (drivers/serial), driven by poll().
#ifndef PV_MONITOR_HOST_LINK_H
#define PV_MONITOR_HOST_LINK_H

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "pitvol/link.h"
#include "pitvol/serial.h"

namespace pv::monitor {

using Handler = std::function<void(const pv_link_rx_t &)>;

class HostLink {
 public:
  HostLink();
  ~HostLink();
  HostLink(const HostLink &) = delete;
  HostLink &operator=(const HostLink &) = delete;

  // Opens the port raw 8N1 at baud. On failure *err says why and what to do.
  bool open(const std::string &port, uint32_t baud, std::string *err);

  // Moves bytes for at most timeout_ms (returns earlier once something
  // arrived); each received message goes to on_msg. false: the port failed.
  // extra_fd (if >= 0) is polled too; *extra_ready says it is readable.
  bool pump(int timeout_ms, const Handler &on_msg, std::string *err, int extra_fd = -1,
            bool *extra_ready = nullptr);

  // Queues cmd again under its first sequence number (a repeat).
  bool post_again(const pitvol_Message &cmd, uint32_t seq, std::string *err);

  // Queues a message without waiting for an answer; its sequence number.
  bool post(const pitvol_Message &msg, uint32_t *seq, std::string *err);

  enum class Reply { Ack, Nack, Timeout, PortError };
  // Sends a command and waits for its Ack/Nack, repeating the same frame
  // every retry_ms, at most tries times. Other messages go to on_msg while
  // waiting (a GetResults' results arrive this way).
  Reply command(const pitvol_Message &cmd, pv_link_rx_t *reply, const Handler &on_msg,
                int retry_ms, int tries, std::string *err);

  const pv_link_stats_t &stats() const;

 private:
  pv_serial_t port_{-1, 0, 0};
  std::unique_ptr<pv_link_t> link_;
};

}  // namespace pv::monitor

#endif
