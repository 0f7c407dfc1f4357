// Serial driver over a real pseudo-terminal pair (openpty): raw 8N1 at the
// asked rate, every byte value passes untouched, reads and writes never
// block, a vanished peer reads as a hangup, and the link runs over it.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pitvol/link.h"
#include "pitvol/serial.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

struct Pty {
  int master = -1;
  std::string slave_path;
};

Pty make_pty() {
  Pty p;
  int slave = -1;
  char name[256];
  assert_int_equal(openpty(&p.master, &slave, name, nullptr, nullptr), 0);
  close(slave);  // the driver opens it by name, as on the board
  p.slave_path = name;
  return p;
}

void opens_raw_8n1_non_blocking_at_the_asked_rate(void **) {
  Pty p = make_pty();
  pv_serial_t port;
  assert_int_equal(pv_serial_open(&port, p.slave_path.c_str(), 921600), PV_SERIAL_OK);
  termios t{};
  assert_int_equal(tcgetattr(pv_serial_fd(&port), &t), 0);
  assert_int_equal(cfgetispeed(&t), B921600);
  assert_int_equal(cfgetospeed(&t), B921600);
  assert_int_equal(t.c_cflag & CSIZE, CS8);
  assert_int_equal(t.c_cflag & (PARENB | CSTOPB | CRTSCTS), 0);
  assert_int_equal(t.c_lflag & (ICANON | ECHO | ISIG), 0);
  assert_int_equal(t.c_cc[VMIN], 1);
  assert_int_equal(t.c_iflag & (IXON | ICRNL | ISTRIP), 0);
  assert_int_equal(t.c_oflag & OPOST, 0);
  assert_true(fcntl(pv_serial_fd(&port), F_GETFL) & O_NONBLOCK);
  pv_serial_close(&port);
  assert_int_equal(pv_serial_open(&port, p.slave_path.c_str(), 9600), PV_SERIAL_OK);
  assert_int_equal(tcgetattr(pv_serial_fd(&port), &t), 0);
  assert_int_equal(cfgetospeed(&t), B9600);
  pv_serial_close(&port);
  close(p.master);
}

void refuses_bad_rates_paths_and_files(void **) {
  pv_serial_t port;
  Pty p = make_pty();
  assert_int_equal(pv_serial_open(&port, p.slave_path.c_str(), 12345), PV_SERIAL_ERR_BAUD);
  assert_int_equal(pv_serial_open(&port, "/nonexistent/tty", 115200), PV_SERIAL_ERR_OPEN);
  char file[] = "/tmp/pv-serial-XXXXXX";
  const int fd = mkstemp(file);
  assert_true(fd >= 0);
  close(fd);
  assert_int_equal(pv_serial_open(&port, file, 115200), PV_SERIAL_ERR_NOT_A_TTY);
  unlink(file);
  assert_int_equal(port.fd, -1);
  assert_non_null(pv_serial_status_message(PV_SERIAL_ERR_NOT_A_TTY));
  close(p.master);
}

void every_byte_value_passes_both_ways_untouched(void **) {
  Pty p = make_pty();
  pv_serial_t port;
  assert_int_equal(pv_serial_open(&port, p.slave_path.c_str(), 115200), PV_SERIAL_OK);
  std::vector<uint8_t> all(256);
  for (int i = 0; i < 256; ++i) all[size_t(i)] = uint8_t(i);  // \r \n ^C ^S ^Q 0x7f ...
  // board -> host
  size_t w = 0;
  assert_int_equal(pv_serial_write(&port, all.data(), all.size(), &w), PV_SERIAL_OK);
  assert_int_equal(w, 256);
  std::vector<uint8_t> got;
  while (got.size() < 256) {
    uint8_t b[512];
    const ssize_t r = read(p.master, b, sizeof b);
    assert_true(r > 0);
    got.insert(got.end(), b, b + r);
  }
  assert_true(got == all);
  // host -> board; nothing there yet reads as 0 bytes, at once.
  size_t n = 99;
  uint8_t buf[512];
  assert_int_equal(pv_serial_read(&port, buf, sizeof buf, &n), PV_SERIAL_OK);
  assert_int_equal(n, 0);
  assert_int_equal(write(p.master, all.data(), all.size()), 256);
  got.clear();
  for (int tries = 0; got.size() < 256 && tries < 1000; ++tries) {
    pollfd pfd{pv_serial_fd(&port), POLLIN, 0};
    poll(&pfd, 1, 1000);
    assert_int_equal(pv_serial_read(&port, buf, sizeof buf, &n), PV_SERIAL_OK);
    got.insert(got.end(), buf, buf + n);
  }
  assert_true(got == all);
  pv_serial_close(&port);
  close(p.master);
}

void a_peer_that_never_reads_does_not_block_the_writer(void **) {
  Pty p = make_pty();
  pv_serial_t port;
  assert_int_equal(pv_serial_open(&port, p.slave_path.c_str(), 115200), PV_SERIAL_OK);
  std::vector<uint8_t> chunk(4096, 0x55);
  size_t total = 0, w = 0;
  int calls = 0;
  do {  // the pty buffer fills; then writes take 0 bytes instead of waiting
    assert_int_equal(pv_serial_write(&port, chunk.data(), chunk.size(), &w), PV_SERIAL_OK);
    total += w;
  } while (w > 0 && ++calls < 10000);
  assert_true(w == 0);
  assert_true(total > 0 && total < 16u * 1024u * 1024u);
  // Once the host reads, writing goes on.
  std::vector<uint8_t> sink(total);
  size_t drained = 0;
  while (drained < 4096) {
    const ssize_t r = read(p.master, sink.data(), sink.size());
    assert_true(r > 0);
    drained += size_t(r);
  }
  assert_int_equal(pv_serial_write(&port, chunk.data(), 16, &w), PV_SERIAL_OK);
  assert_int_equal(w, 16);
  pv_serial_close(&port);
  close(p.master);
}

void a_vanished_peer_reads_as_hangup(void **) {
  Pty p = make_pty();
  pv_serial_t port;
  assert_int_equal(pv_serial_open(&port, p.slave_path.c_str(), 115200), PV_SERIAL_OK);
  close(p.master);
  uint8_t buf[16];
  size_t n = 0;
  assert_int_equal(pv_serial_read(&port, buf, sizeof buf, &n), PV_SERIAL_HANGUP);
  pv_serial_close(&port);
}

long serial_write(void *ctx, const uint8_t *d, size_t n) {
  size_t w = 0;
  return pv_serial_write(static_cast<pv_serial_t *>(ctx), d, n, &w) == PV_SERIAL_OK ? long(w) : -1;
}

// The event loop of the header comment, both ends in one process: 300
// results and statuses board -> host through the pty, commands host ->
// board answered with Acks.
void the_link_runs_over_the_pty_in_a_poll_loop(void **) {
  Pty p = make_pty();
  pv_serial_t board_port, host_port;
  assert_int_equal(pv_serial_open(&board_port, p.slave_path.c_str(), 115200), PV_SERIAL_OK);
  assert_int_equal(pv_serial_adopt(&host_port, p.master, 115200), PV_SERIAL_OK);
  static pv_link_t board, host;
  pv_link_init(&board, 0);
  pv_link_init(&host, 1000);
  uint32_t next_result = 1, results_seen = 0, acks_seen = 0, commands_seen = 0;
  std::vector<uint32_t> ids;
  for (int iter = 0; iter < 200000 && (results_seen < 300 || acks_seen < 6); ++iter) {
    // Board: a result when there is room, a status every time (lossy).
    if (next_result <= 300) {
      pitvol_Message m = pitvol_Message_init_zero;
      m.which_body = pitvol_Message_result_tag;
      m.body.result.id = next_result;
      m.body.result.volume_cm3 = 1000.0 + next_result;
      if (pv_link_send(&board, &m, PV_LINK_RELIABLE, nullptr) == PV_LINK_OK) next_result++;
    }
    pitvol_Message st = pitvol_Message_init_zero;
    st.which_body = pitvol_Message_status_tag;
    st.body.status.points = uint64_t(iter);
    const pv_link_status_t sst = pv_link_send(&board, &st, PV_LINK_LOSSY, nullptr);
    assert_true(sst == PV_LINK_OK || sst == PV_LINK_DROPPED);  // lossy: a full queue drops it
    pollfd fds[2] = {
        {pv_serial_fd(&board_port), short(POLLIN | (pv_link_tx_pending(&board) ? POLLOUT : 0)), 0},
        {pv_serial_fd(&host_port), short(POLLIN | (pv_link_tx_pending(&host) ? POLLOUT : 0)), 0}};
    assert_true(poll(fds, 2, 1000) > 0);
    uint8_t buf[256];
    size_t n = 0;
    if (fds[0].revents & POLLOUT) assert_int_equal(pv_link_tx_flush(&board, serial_write, &board_port), PV_LINK_OK);
    if (fds[1].revents & POLLOUT) assert_int_equal(pv_link_tx_flush(&host, serial_write, &host_port), PV_LINK_OK);
    if (fds[0].revents & POLLIN) {
      assert_int_equal(pv_serial_read(&board_port, buf, sizeof buf, &n), PV_SERIAL_OK);
      for (size_t at = 0; at < n;) {
        pv_link_rx_t rx;
        int got = 0;
        at += pv_link_feed(&board, buf + at, n - at, &rx, &got);
        if (got) {
          assert_true(pv_link_is_command(&rx.msg));
          commands_seen++;
          assert_int_equal(pv_link_ack(&board, rx.seq, 1, next_result - 1, 0), PV_LINK_OK);
        }
      }
    }
    if (fds[1].revents & POLLIN) {
      assert_int_equal(pv_serial_read(&host_port, buf, sizeof buf, &n), PV_SERIAL_OK);
      for (size_t at = 0; at < n;) {
        pv_link_rx_t rx;
        int got = 0;
        at += pv_link_feed(&host, buf + at, n - at, &rx, &got);
        if (!got) continue;
        if (rx.msg.which_body == pitvol_Message_result_tag) {
          ids.push_back(rx.msg.body.result.id);
          if (++results_seen % 50 == 0) {  // a command now and then
            pitvol_Message cmd = pitvol_Message_init_zero;
            cmd.which_body = pitvol_Message_get_hello_tag;
            assert_int_equal(pv_link_send(&host, &cmd, PV_LINK_RELIABLE, nullptr), PV_LINK_OK);
          }
        } else if (rx.msg.which_body == pitvol_Message_ack_tag) {
          acks_seen++;
        }
      }
    }
  }
  assert_int_equal(results_seen, 300);
  for (uint32_t i = 0; i < 300; ++i) assert_int_equal(ids[i], i + 1);
  assert_int_equal(commands_seen, 6);
  assert_int_equal(acks_seen, 6);
  assert_int_equal(host.stats.frames_corrupt, 0);
  assert_int_equal(board.stats.frames_corrupt, 0);
  pv_serial_close(&board_port);
  pv_serial_close(&host_port);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(opens_raw_8n1_non_blocking_at_the_asked_rate),
      cmocka_unit_test(refuses_bad_rates_paths_and_files),
      cmocka_unit_test(every_byte_value_passes_both_ways_untouched),
      cmocka_unit_test(a_peer_that_never_reads_does_not_block_the_writer),
      cmocka_unit_test(a_vanished_peer_reads_as_hangup),
      cmocka_unit_test(the_link_runs_over_the_pty_in_a_poll_loop),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
