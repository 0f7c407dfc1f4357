#!/usr/bin/env bash
# The board application on this host: installs what is missing, builds
# (Release, build/), makes a simulated scan of a pit with known volume
# (pitvol-sim, corpus family cylinder seed 3) and runs pitvol-board-emu --
# the same code as pitvol-board, with the scanner emulated on umockdev and
# the PNG display -- through every screen, pressing its buttons through a
# named pipe:
#   1. no scanner at start, START pressed (armed), scanner plugged in,
#      scanning with live estimates, unplugged mid-scan (PAUSED), plugged
#      back in, scan ends, MEASURING, RESULT, ENTER -> READY;
#   2. a scan too sparse to measure -> REFUSED.
# Leaves one PNG and one text dump per screen in build/board-demo/screens/
# (scanning_live: a live screen from early in the scan, with its hint)
# and prints the board's log. Usage: host_tools/board-demo.sh [--fps F]
set -euo pipefail
cd "$(dirname "$0")/.."
fps=20
[ "${1:-}" = "--fps" ] && fps=$2

toolchain/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default --target pitvol-board-emu pitvol-board pitvol-sim pitvol

out=build/board-demo
rm -rf "$out"
mkdir -p "$out/screens"
build/bin/pitvol-sim scan --family cylinder --seed 3 --out "$out/cyl" >/dev/null
build/bin/pitvol-sim scan --family cylinder --seed 3 --points 3000 --out "$out/small" >/dev/null

pid=
run() { # log, then pitvol-board-emu arguments
  local log=$1
  shift
  build/bin/pitvol-board-emu "$@" --input "pipe:$out/buttons" >"$log" 2>&1 &
  pid=$!
}
wait_for() { # log, regex
  for _ in $(seq 1 900); do
    grep -Eqs "$2" "$1" && return 0  # -s: the log appears when the board starts
    kill -0 "$pid" 2>/dev/null || { cat "$1"; echo "board-demo: the board stopped" >&2; exit 1; }
    sleep 0.1
  done
  echo "board-demo: timed out waiting for '$2'" >&2
  exit 1
}
press() { echo "$1" >"$out/buttons"; }
finish() { kill -TERM "$pid"; wait "$pid" || true; }

# 1. The whole story with one scan.
run "$out/board.log" "$out/cyl.frames" --fps "$fps" --absent-for 1500 --unplug-at-frame 35 \
  --display "png:$out/screens"
wait_for "$out/board.log" "state no_scanner"
press start
# Keep one live screen that still asks for part of the wall (the last
# scanning screen shows the wall complete).
s=$out/screens
(for _ in $(seq 1 400); do
  # A pair is consistent if neither file changed while both were copied;
  # keep it if the text shows a running volume and an unseen band.
  if cp "$s/scanning.png" "$s/live1.png" 2>/dev/null && cp "$s/scanning.txt" "$s/live1.txt" &&
    cmp -s "$s/scanning.png" "$s/live1.png" && cmp -s "$s/scanning.txt" "$s/live1.txt" &&
    grep -q "not seen" "$s/live1.txt" && grep -q "|~" "$s/live1.txt"; then
    mv "$s/live1.png" "$s/scanning_live.png"
    mv "$s/live1.txt" "$s/scanning_live.txt"
    break
  fi
  sleep 0.05
done) &
wait_for "$out/board.log" "state paused"
wait_for "$out/board.log" "screen result"
press enter
wait_for "$out/board.log" "screen idle"
finish

# 2. A refusal, in its own directory (its screens.log would replace the first).
run "$out/refused.log" "$out/small.frames" --fps "$fps" --display "png:$out/refused"
wait_for "$out/refused.log" "state idle"
press start
wait_for "$out/refused.log" "screen refused"
finish
cp "$out/refused/refused.png" "$out/refused/refused.txt" "$out/screens/"
rm -f "$out/screens/live1.png" "$out/screens/live1.txt"

grep -v "event tick" "$out/board.log"
echo
echo "pitvol measure on the same scan:"
build/bin/pitvol measure "$out/cyl.ply" | head -3
echo
echo "screens (PNG + text dump) in $out/screens/:"
ls "$out/screens"
