"""pitvol-board under systemd's service protocol, without systemd: this
test plays the service manager. It binds the notify socket, starts the
board (no scanner, PNG display, no buttons, no link) with NOTIFY_SOCKET,
WATCHDOG_USEC and WATCHDOG_PID as systemd sets them for Type=notify and
WatchdogSec=, and checks READY=1, then WATCHDOG=1 every half period, none
while the process is stopped (what makes systemd restart a hung board),
and a clean exit on SIGTERM. Then the board under a unit whose notify
socket is not usable: it must refuse to start (exit 3) and name the fault
by its code (PV_BOARD_WATCHDOG_ERR_*, docs/errors.md).

usage: test_watchdog.py WORK_DIR [RUNNER ...] PITVOL_BOARD
RUNNER: e.g. qemu-aarch64-static LOADER --library-path DIR (the board build).
Run with /usr/bin/python3.
"""
import os
import signal
import socket
import subprocess
import sys
import time

PERIOD_US = 400_000  # pings every 200 ms


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def collect(sock, seconds):
    got = []
    end = time.monotonic() + seconds
    while True:
        left = end - time.monotonic()
        if left <= 0:
            return got
        sock.settimeout(left)
        try:
            got.append(sock.recv(4096).decode())
        except socket.timeout:
            return got


def board_args(work):
    return ["--display", "png:" + os.path.join(work, "screens"), "--input", "none",
            "--set", "serial=none", "--set", "result_log=none"]


def refuses(work, command, notify_socket, code):
    """The board with NOTIFY_SOCKET=notify_socket exits 3 naming code."""
    env = dict(os.environ, NOTIFY_SOCKET=notify_socket)
    r = subprocess.run(command + board_args(work), env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=60)
    if r.returncode != 3 or f"[{code}]" not in r.stdout:
        fail(f"NOTIFY_SOCKET={notify_socket}: exit {r.returncode}, want 3 and [{code}]:\n{r.stdout}")
    print(f"ok: NOTIFY_SOCKET={notify_socket} refused with {code}")


def main(argv):
    work, command = argv[0], argv[1:]
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, "notify.sock")
    if os.path.exists(path):
        os.unlink(path)
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(path)
    env = dict(os.environ, NOTIFY_SOCKET=path, WATCHDOG_USEC=str(PERIOD_US))
    # WATCHDOG_PID is the service's main PID, set between fork and exec as
    # systemd does: the shell's $$, kept by exec (and by qemu-user).
    board = subprocess.Popen(
        ["sh", "-c", 'WATCHDOG_PID=$$ exec "$@"', "sh"] + command + board_args(work),
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        sock.settimeout(30)  # the board's start under qemu on a busy machine
        try:
            first = sock.recv(4096).decode()
        except socket.timeout:
            first = None
        if first != "READY=1":
            fail(f"the first message is not READY=1: {first}")
        steady = collect(sock, 2.0)
        n = steady.count("WATCHDOG=1")
        # 10 pings in 2 s; qemu and a busy machine may delay a few.
        if n < 5 or n > 12:
            fail(f"{n} pings in 2 s, want about 10")
        print(f"ok: READY=1, then {n} pings in 2 s (period {PERIOD_US // 1000} ms)")
        board.send_signal(signal.SIGSTOP)
        quiet = collect(sock, 1.0)
        board.send_signal(signal.SIGCONT)
        # A ping already in flight when the signal landed may still arrive.
        if quiet.count("WATCHDOG=1") > 1:
            fail(f"{quiet.count('WATCHDOG=1')} pings while the board was stopped")
        print("ok: no pings while the board is stopped")
        if not collect(sock, 1.5).count("WATCHDOG=1"):
            fail("no pings after SIGCONT")
        board.send_signal(signal.SIGTERM)
        out, _ = board.communicate(timeout=30)
    finally:
        if board.poll() is None:
            board.kill()
    if board.returncode != 0:
        fail(f"exit {board.returncode} on SIGTERM:\n{out}")
    if "systemd watchdog, a ping every 200 ms" not in out:
        fail(f"the board did not report its watchdog:\n{out}")
    print("ok: clean exit on SIGTERM;", out.strip().splitlines()[-1])
    refuses(work, command, "relative/notify.sock", "PV_BOARD_WATCHDOG_ERR_SOCKET_PATH")
    refuses(work, command, os.path.join(work, "no-such.sock"), "PV_BOARD_WATCHDOG_ERR_NOTIFY")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
