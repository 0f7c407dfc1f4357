#!/usr/bin/env bash
# End-to-end tests of the board application (label e2e): pitvol-board-emu
# (the same code as pitvol-board, the real libusb driver, the scanner
# emulated on umockdev, the PNG display) driven through its button pipe.
# Assertions read what the screens laid out (DIR/<screen>.txt and
# DIR/screens.log, written beside the PNGs) and the board's log; the
# reference volume comes from `pitvol measure` on the same scan's PLY.
#
#   board_e2e.sh CASE BIN_DIR FIXTURE_DIR WORK_DIR
# Environment (the board build under qemu, tests/e2e/CMakeLists.txt):
#   PV_E2E_RUN       runs the board's programs: "umockdev-wrapper
#                    qemu-aarch64-static SYSROOT/lib/ld-linux-aarch64.so.1
#                    --library-path ..." (docs/targets.md); empty natively
#                    (pitvol-board-emu runs itself under umockdev-wrapper)
#   PV_E2E_HOST_BIN  the host's pitvol (reference) and pitvol-monitor;
#                    default BIN_DIR
# CASE: full_scan | stop_mid_scan | unplug_idle | unplug_replug | unplug_end | no_scanner_at_start | refused
#       | serial_link (pitvol-monitor over a pseudo-terminal, result log, density)
set -uo pipefail
case_name=$1 bin=$2 fixtures=$3 work=$4/$1

command -v umockdev-wrapper >/dev/null || { echo "SKIP: umockdev-wrapper not installed"; exit 77; }

fail() { echo "FAIL [$case_name]: $*" >&2; [ -f "$work/board.log" ] && sed 's/^/  log: /' "$work/board.log" | grep -v "event tick" | tail -30 >&2; stop_board; exit 1; }
pass() { echo "ok   [$case_name]: $*"; }

read -ra run <<<"${PV_E2E_RUN:-}"
host_bin=${PV_E2E_HOST_BIN:-$bin}
board_emu() { "${run[@]}" "$bin/pitvol-board-emu" "$@"; }

rm -rf "$work"
mkdir -p "$work"
pipe=$work/buttons
screens=$work/screens
pid=

start_board() { # frames file, then pitvol-board-emu options
  # A simple command, not the function: $! is then the program itself.
  "${run[@]}" "$bin/pitvol-board-emu" "$@" --display "png:$screens" --input "pipe:$pipe" \
    >"$work/board.log" 2>&1 &
  pid=$!
}
stop_board() {
  [ -n "$pid" ] || return 0
  kill -TERM "$pid" 2>/dev/null
  wait "$pid"
  local rc=$?
  pid=
  return $rc
}
# wait_log REGEX [SECONDS [N]]: until the board's log has N (default 1)
# matching lines. The board logs "screen X" once screen X is on display.
wait_log() {
  local deadline=$((SECONDS + ${2:-60})) n=${3:-1}
  local c
  # (grep -c prints nothing for a log not written yet: that is 0.)
  until c=$(grep -Ec -- "$1" "$work/board.log" 2>/dev/null); [ "${c:-0}" -ge "$n" ]; do
    [ $SECONDS -lt $deadline ] || fail "timed out waiting for '$1'"
    kill -0 "$pid" 2>/dev/null || fail "board exited while waiting for '$1'"
    sleep 0.1
  done
}
press() { echo "$1" >"$pipe"; }
# has FILE FIXED-STRING: the screen text contains it.
has() { grep -qF -- "$2" "$1" || fail "$(basename "$1") lacks '$2'"; }

# The reference: pitvol measure on the PLY of the same scan.
reference() { # ply [pitvol measure options] -> "STATUS VOLUME"
  local json
  json=$("$host_bin/pitvol" measure "$@" --json 2>/dev/null)
  local st vol
  st=$(sed -n 's/.*"status": "\([A-Z_]*\)".*/\1/p' <<<"$json")
  vol=$(sed -n 's/.*"volume_cm3": \([^,]*\),.*/\1/p' <<<"$json")
  echo "$st $vol"
}
result_field() { # name -> value from the board's result line
  sed -n "s/^pitvol-board: result .*\b$1=\([^ ]*\).*/\1/p" "$work/board.log" | tail -1
}
png_ok() { # every named screen has a PNG with the PNG signature
  for s in "$@"; do
    [ "$(head -c 8 "$screens/$s.png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
      fail "no valid $s.png"
  done
}
check_result_equals_reference() { # ply
  read -r ref_st ref_vol <<<"$(reference "$1")"
  [ "$ref_st" = PV_OK ] || fail "reference measure failed: $ref_st"
  # The board prints %.17g, pitvol's JSON the shortest form that reads
  # back the same: the same double in the board's form (awk reads and
  # prints doubles).
  ref_vol=$(awk -v v="$ref_vol" 'BEGIN { printf "%.17g", v + 0 }')
  local vol
  vol=$(result_field volume_cm3)
  [ "$vol" = "$ref_vol" ] || fail "board volume $vol != pitvol measure $ref_vol (must match bit for bit)"
  has "$screens/result.txt" "result volume_cm3=$ref_vol "
  has "$screens/result.txt" "|$(printf '%.1f' "$ref_vol")"
  pass "volume $vol cm3 equals pitvol measure bit for bit"
}
check_allocations() {
  local line
  line=$(grep "allocations after start" "$work/board.log") || fail "no allocation report"
  if grep -q "board=-1" <<<"$line"; then # sanitizer build: ASan owns malloc
    pass "allocations not counted in this build"
    return
  fi
  grep -q "board=0 push=0 " <<<"$line" || fail "allocations after start: $line"
  # The counter is live: it sees libusb's own allocations (the core's
  # estimate/finish allocate nothing: measure=0 is asserted below).
  grep -Eq "usb=[1-9]" <<<"$line" || fail "the allocation counter saw nothing: $line"
  grep -q " measure=0" <<<"$line" || fail "estimate/finish allocated: $line"
  pass "no allocation in the board or push after start (${line#*: })"
}

cyl=$fixtures/cyl
small=$fixtures/small

case $case_name in
full_scan)
  start_board "$cyl.frames" --fps 15  # ~5 s of scanning: several live estimates
  wait_log "screen idle" 30
  has "$screens/idle.txt" "press START"
  press start
  wait_log "screen result" 90
  check_result_equals_reference "$cyl.ply"
  # Live estimates while scanning: each one is drawn with its coverage
  # bars (how many fit in the ~5 s scan depends on the machine: not asserted).
  n=$(grep -c "^coverage [01]" "$screens/screens.log")
  e=$(grep -c "pitvol-board: estimate " "$work/board.log")
  [ "$e" -ge 1 ] || fail "no live estimate while scanning"
  [ "$n" -ge 1 ] || fail "$e estimates but no scanning screen with wall coverage"
  if grep -q "pitvol-board: estimate PV_OK" "$work/board.log"; then
    grep -q "^text .*|~[0-9]*\.[0-9] cm³" "$screens/screens.log" || fail "no running volume shown"
  fi
  has "$screens/scanning.txt" "points "
  has "$screens/measuring.txt" "please wait"
  pass "$e live estimates, $n scanning screens with coverage"
  press enter
  wait_log "screen idle" 10 2
  has "$screens/idle.txt" "last: $(printf '%.1f' "$(result_field volume_cm3)") cm³"
  stop_board || fail "board did not exit cleanly on SIGTERM"
  check_allocations
  png_ok boot idle scanning measuring result
  ;;
unplug_replug)
  start_board "$cyl.frames" --fps 20 --unplug-at-frame 30 --replug-after 500
  wait_log "state idle" 30
  press start
  wait_log "screen paused" 60
  has "$screens/paused.txt" "scanner unplugged"
  has "$screens/paused.txt" "points kept"
  wait_log "screen result" 90
  grep -q "event scanner_arrived" <(grep -A100 "state paused" "$work/board.log") || fail "no replug seen"
  check_result_equals_reference "$cyl.ply"
  [ "$(result_field board_warnings)" = 0x0 ] || fail "a resumed scan must carry no unplug warning"
  stop_board || fail "board did not exit cleanly"
  check_allocations
  png_ok paused result
  ;;
unplug_end)
  start_board "$cyl.frames" --fps 20 --unplug-at-frame 50 --no-replug
  wait_log "state idle" 30
  press start
  wait_log "state paused" 60
  press stop
  wait_log "screen (result|refused)" 60
  [ "$(result_field board_warnings)" = 0x1 ] || fail "result lacks the ended-while-unplugged warning"
  if grep -q "state result" "$work/board.log"; then
    has "$screens/result.txt" "ended while unplugged"
    read -r _ ref_vol <<<"$(reference "$cyl.ply")"
    [ "$(result_field volume_cm3)" != "$ref_vol" ] || fail "a partial scan cannot equal the whole"
  else
    has "$screens/refused.txt" "scan ended while unplugged"
  fi
  pass "partial scan measured with the warning ($(result_field volume_cm3) cm3)"
  stop_board || fail "board did not exit cleanly"
  ;;
stop_mid_scan)
  # The technician presses STOP: the board tells the scanner, which ends
  # the scan with END_OF_SCAN; what arrived is measured, no warning.
  start_board "$cyl.frames" --fps 10
  wait_log "state idle" 30
  press start
  wait_log "pitvol-board: estimate PV_OK" 90
  press stop
  wait_log "screen (result|refused)" 60
  grep -q "event scan_ended" "$work/board.log" || fail "the scanner did not end the scan"
  pts=$(result_field points_in)
  total=$(sed -n 's/.*"points": \([0-9]*\),.*/\1/p' "$cyl.json")
  [ "$pts" -gt 0 ] && [ "$pts" -lt "$total" ] || fail "points_in $pts: not a part of the $total-point scan"
  [ "$(result_field board_warnings)" = 0x0 ] || fail "a stopped scan carries no unplug warning"
  pass "stopped after $pts points: $(result_field status) $(result_field volume_cm3)"
  stop_board || fail "board did not exit cleanly"
  ;;
unplug_idle)
  # Unplugged while READY (no transfer in flight): the driver hears the
  # hotplug "left" event, the board says so, and is ready again on replug.
  start_board "$cyl.frames" --unplug-after 1500 --replug-after 1500
  wait_log "screen idle" 30
  wait_log "screen no_scanner" 30
  has "$screens/no_scanner.txt" "no USB"
  wait_log "screen idle" 30 2
  has "$screens/idle.txt" "USB ok"
  pass "unplug and replug seen while ready"
  stop_board || fail "board did not exit cleanly"
  ;;
no_scanner_at_start)
  start_board "$cyl.frames" --fps 20 --absent-for 2000
  wait_log "screen no_scanner" 30
  has "$screens/no_scanner.txt" "plug it in"
  press start # armed: the scan starts when the scanner arrives
  wait_log "state scanning" 30
  grep -q "scan starts when plugged" "$screens/screens.log" || fail "armed screen not shown"
  grep -q "event scanner_arrived" "$work/board.log" || fail "arrival not seen"
  wait_log "screen result" 90
  check_result_equals_reference "$cyl.ply"
  stop_board || fail "board did not exit cleanly"
  png_ok no_scanner scanning result
  ;;
refused)
  # The paper's method, named on both sides: which status refuses this
  # sparse scan is the method's business, that board and CLI agree is ours.
  echo "method = paper" >"$work/paper.conf"
  start_board "$small.frames" --fps 20 --set core.method=paper
  wait_log "state idle" 30
  press start
  wait_log "screen refused" 60
  read -r ref_st _ <<<"$(reference "$small.ply" --config "$work/paper.conf")"
  [ "$ref_st" != PV_OK ] || fail "fixture unexpectedly measurable"
  has "$screens/refused.txt" "refused status=$ref_st"
  has "$screens/refused.txt" "no volume"
  [ "$(result_field status)" = "$ref_st" ] || fail "board status $(result_field status) != $ref_st"
  # A 5,837-point scan: the advice is the point count (pitvol/advice.h),
  # the same on the screen as from pitvol measure.
  grep -q "^text .*|too few points (5 837)" "$screens/refused.txt" || fail "reason not shown"
  grep -q "^text .*|rescan slowly, all round" "$screens/refused.txt" || fail "what to do not shown"
  local_cli=$("$host_bin/pitvol" measure "$small.ply" --config "$work/paper.conf" 2>&1)
  grep -q "too few points (5837)" <<<"$local_cli" || fail "pitvol measure gives other advice: $local_cli"
  pass "refused with $ref_st, as pitvol measure"
  stop_board || fail "board did not exit cleanly"
  png_ok refused
  ;;
serial_link)
  # The serial link (docs/protocol/serial.md) over a real pseudo-terminal: pitvol-monitor
  # against the board, every message of the protocol exchanged; the
  # monitor's result equals pitvol measure bit for bit; the result log keeps
  # it through a restart of the board.
  mon() { "$host_bin/pitvol-monitor" "$work/port" "$@"; }
  # A port that is not there: no link, said in the log; the board still works.
  start_board "$cyl.frames" --set "serial=$work/absent-tty"
  wait_log "screen idle" 30
  grep -q "serial link off: $work/absent-tty: " "$work/board.log" || fail "an absent port not reported"
  stop_board || fail "board did not exit cleanly"
  # A result log that cannot be opened stops the start (exit 3) and says why.
  board_emu "$cyl.frames" --display "png:$screens" --input none \
    --set "result_log=$work/absent/results" >"$work/board.log" 2>&1
  rc=$?
  [ $rc -eq 3 ] || fail "unopenable result log: exit $rc, want 3"
  grep -q "result log $work/absent/results cannot be opened" "$work/board.log" || fail "no reason given"
  pass "absent port: board runs without the link; unopenable log: exit 3 with the reason"
  link_opts=(--serial-pty "$work/port" --set "result_log=$work/results" --set max_dry_density_kg_m3=1850
             --set device_id=PV-E2E-1)
  start_board "$cyl.frames" --fps 20 "${link_opts[@]}"
  wait_log "screen idle" 30
  grep -q "serial link on pty" "$work/board.log" || fail "link not on"
  # GetHello -> Hello + Ack
  mon hello >"$work/hello.txt" 2>&1 || fail "hello: $(cat "$work/hello.txt")"
  grep -q "device PV-E2E-1, protocol 1, results 0..0" "$work/hello.txt" || fail "hello: $(cat "$work/hello.txt")"
  # SetMass, SetMoisture -> Ack; out of range and StopScan while idle -> Nack (exit 1)
  mon set-mass 23500 >/dev/null 2>&1 || fail "set-mass"
  mon set-moisture 12.5 >/dev/null 2>&1 || fail "set-moisture"
  mon set-mass -1 >/dev/null 2>"$work/nack.txt" && fail "a negative mass was taken"
  grep -q "outside 50 .. 100000 g" "$work/nack.txt" || fail "no reason for the refused mass: $(cat "$work/nack.txt")"
  mon stop >/dev/null 2>&1 && fail "StopScan while idle was taken"
  # The test record (SetRecord): text and the requirement; absurd or
  # hostile values refused by the board with their range or reason.
  mon set-test-id FDT-E2E-1 >/dev/null 2>&1 || fail "set-test-id"
  mon set-location "STA 0+100, 2.5 m LT, lift 2" >/dev/null 2>&1 || fail "set-location"
  mon set-operator "A. Tester" >/dev/null 2>&1 || fail "set-operator"
  mon set-required-compaction 95 >/dev/null 2>&1 || fail "set-required-compaction"
  mon set-required-compaction 1e308 >/dev/null 2>"$work/nack.txt" && fail "a requirement of 1e308 % was taken"
  grep -q "outside 50 .. 110 %" "$work/nack.txt" || fail "no range for the requirement: $(cat "$work/nack.txt")"
  mon set-max-dry-density 1.85 >/dev/null 2>"$work/nack.txt" && fail "a max dry density in g/cm3 was taken"
  grep -q "times 1000" "$work/nack.txt" || fail "no hint for g/cm3: $(cat "$work/nack.txt")"
  mon set-mass 0x10 >/dev/null 2>&1; [ $? -eq 2 ] || fail "set-mass 0x10 not a usage error"
  mon set-operator $'A\x1b[2J' >/dev/null 2>"$work/nack.txt" && fail "a control character was taken"
  grep -q "control character" "$work/nack.txt" || fail "no reason for the control character"
  # StartScan through watch: Status while scanning, the Result when the
  # scanner ends the scan.
  printf 'start\n' | mon watch --json --count 1 --seconds 90 >"$work/watch.json" || fail "watch"
  grep -q '"type": "ack", "command": "start"' "$work/watch.json" || fail "start not acknowledged"
  nstat=$(grep -c '"type": "status", "state": "scanning"' "$work/watch.json")
  [ "$nstat" -ge 2 ] || fail "$nstat status messages while scanning"
  grep -q '"type": "status", "state": "scanning", "points": [1-9]' "$work/watch.json" || fail "no points in status"
  if grep -q "pitvol-board: estimate PV_OK" "$work/board.log"; then
    grep -q '"running_volume_cm3": [1-9].*"coverage": \[[0-9]' "$work/watch.json" || fail "no running volume/coverage in status"
  fi
  grep '"type": "result"' "$work/watch.json" >"$work/result1.json"
  [ "$(wc -l <"$work/result1.json")" -eq 1 ] || fail "want one result ($(cat "$work/watch.json" | tail -3))"
  grep -q '"id": 1, ' "$work/result1.json" || fail "result id: $(cat "$work/result1.json")"
  read -r ref_st ref_vol <<<"$(reference "$cyl.ply")"
  got=$(sed -n 's/.*"volume_cm3": \([^,}]*\).*/\1/p' "$work/result1.json")
  [ "$got" = "$ref_vol" ] || fail "monitor volume $got != pitvol measure $ref_vol"
  [ "$(result_field volume_cm3)" = "$ref_vol" ] || fail "board's own log volume differs"
  pass "monitor result #1: $got cm3 = pitvol measure bit for bit ($nstat status while scanning)"
  # Density from the mass and moisture sent: 23.5 kg, 12.5 %, reference 1850 kg/m3.
  near() { # FIELD WANT: within 1e-9 relative
    local v
    v=$(sed -n "s/.*\"$1\": \([^,}]*\).*/\1/p" "$work/result1.json")
    awk -v a="$v" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a != "" && d <= 1e-9 * b) }' ||
      fail "result 1: $1 = $v, want $2"
  }
  wet=$(awk -v v="$ref_vol" 'BEGIN { printf "%.17g", 23500 / v * 1000 }')
  near wet_kg_m3 "$wet"
  near dry_kg_m3 "$(awk -v w="$wet" 'BEGIN { printf "%.17g", w / 1.125 }')"
  near compaction_percent "$(awk -v w="$wet" 'BEGIN { printf "%.17g", w / 1.125 / 1850 * 100 }')"
  has "$screens/result.txt" "density flags=0x7 "
  # The record and the verdict: 95.6 % (its range) against 95 %: PASS, on
  # the screen, in the result and (after the restart below) in the log.
  grep -q '"test_id": "FDT-E2E-1", "location": "STA 0+100, 2.5 m LT, lift 2", "operator": "A. Tester", "required_compaction_percent": 95, "verdict": "PASS"' \
    "$work/result1.json" || fail "result 1 lacks its record: $(cat "$work/result1.json")"
  has "$screens/result.txt" "|FDT-E2E-1 PASS"
  has "$screens/result.txt" "verdict PASS "
  has "$screens/result.txt" "|wet $(awk -v w="$wet" 'BEGIN { printf "%.3f", w / 1000 }') dry $(awk -v w="$wet" 'BEGIN { printf "%.3f", w / 1125 }') g/cm³"
  has "$screens/result.txt" "|compaction $(awk -v w="$wet" 'BEGIN { printf "%.1f", w / 1.125 / 18.5 }')%"
  pass "density on the RESULT screen and in the Result: wet $wet kg/m3"
  # The mass was used up by that pit; the moisture stays.
  mon watch --json --seconds 2.5 >"$work/after.json" || fail "watch after"
  grep -q '"mass_g": null, "moisture_percent": 12.5' "$work/after.json" || fail "mass not cleared after use"
  # A restart: the result comes back from the log.
  stop_board || fail "board did not exit cleanly"
  grep -Eq "link: [0-9]+ frames sent, [0-9]+ received, 0 corrupt" "$work/board.log" || fail "link counters"
  mv "$work/board.log" "$work/board-1.log"
  # This time the board opens its port by name (serial = /dev/pts/N), as
  # pitvol-board does on /dev/ttyS1.
  start_board "$cyl.frames" --fps 20 "${link_opts[@]}" --serial-by-path
  wait_log "screen idle" 30
  grep -q "serial link on /dev/pts/[0-9]* at 115200 baud" "$work/board.log" || fail "port not opened by name"
  grep -q "result log .*: results 1..1," "$work/board.log" || fail "log not recovered"
  mon fetch --json >"$work/fetch.json" 2>/dev/null || fail "fetch after restart"
  cmp -s "$work/fetch.json" "$work/result1.json" || fail "fetched result differs: $(cat "$work/fetch.json")"
  pass "result #1 read back from the log after a restart, identical"
  # StopScan mid-scan: Ack, then a result #2 (an Error too if no volume).
  # The watch runs until result 2 is there and, if it has no volume, the
  # Error after it (--count 1 would stop before the Error).
  # The monitor itself in the background, not through mon(): killing the
  # function's subshell would leave the monitor running, and it would read
  # the replies meant for the fetch below.
  (printf 'start\n'; sleep 1.5; printf 'stop\n') |
    "$host_bin/pitvol-monitor" "$work/port" watch --json --seconds 120 >"$work/watch2.json" &
  wpid=$!
  deadline=$((SECONDS + 120))
  until grep -q '"type": "result", "id": 2, .*"status": "PV_OK"' "$work/watch2.json" ||
        { grep -q '"type": "result", "id": 2, ' "$work/watch2.json" && grep -q '"type": "error"' "$work/watch2.json"; }; do
    [ $SECONDS -lt $deadline ] && kill -0 "$wpid" 2>/dev/null || break
    sleep 0.1
  done
  kill "$wpid" 2>/dev/null
  wait "$wpid" 2>/dev/null
  ! pgrep -f "pitvol-monitor $work/port watch" >/dev/null || fail "the watch still runs"
  grep -q '"type": "ack", "command": "stop"' "$work/watch2.json" || fail "stop not acknowledged"
  grep -q '"type": "result", "id": 2, ' "$work/watch2.json" || fail "no result 2"
  if ! grep -q '"type": "result", "id": 2, .*"status": "PV_OK"' "$work/watch2.json"; then
    grep -q '"type": "error", "code": [1-9]' "$work/watch2.json" || fail "no Error after a result without volume"
  fi
  grep -q '"wet_kg_m3": null' "$work/watch2.json" || grep -q '"density": null' "$work/watch2.json" ||
    ! grep -q 'wet_kg_m3": [0-9]' "$work/watch2.json" || fail "result 2 has a density without a mass"
  mon fetch >"$work/fetch.csv" 2>/dev/null || fail "fetch 2"
  [ "$(cut -d, -f1 "$work/fetch.csv" | tail -n +2 | tr '\n' ' ')" = "1 2 " ] || fail "log ids: $(cat "$work/fetch.csv")"
  pass "StopScan mid-scan: result #2 ($(sed -n 's/.*"type": "result".*"status": "\([A-Z_]*\)".*/\1/p' "$work/watch2.json"))"
  stop_board || fail "board did not exit cleanly"
  # Line noise on 1 % of the bytes both ways (flips, drops, insertions):
  # commands are repeated until answered, a scan's result still arrives
  # (asked for again by id if its frame was hit), the log comes whole.
  mv "$work/board.log" "$work/board-2.log"
  start_board "$cyl.frames" --fps 20 "${link_opts[@]}" --serial-noise 1 --serial-seed 7
  wait_log "screen idle" 30
  noisy=(--retry-ms 200 --tries 50)
  mon set-mass 23500 "${noisy[@]}" >/dev/null 2>&1 || fail "noisy set-mass"
  printf 'start\n' | mon watch --json --count 1 --seconds 60 "${noisy[@]}" >"$work/watch3.json" 2>/dev/null ||
    fail "noisy watch"
  got=$(sed -n 's/.*"type": "result", "id": 3,.*"volume_cm3": \([^,}]*\).*/\1/p' "$work/watch3.json")
  [ "$got" = "$ref_vol" ] || fail "noisy line: result 3 volume '$got' != $ref_vol"
  mon fetch "${noisy[@]}" >"$work/noisy.csv" 2>"$work/noisy.err" || fail "noisy fetch: $(cat "$work/noisy.err")"
  [ "$(cut -d, -f1 "$work/noisy.csv" | tail -n +2 | tr '\n' ' ')" = "1 2 3 " ] || fail "noisy fetch ids"
  cmp -s <(head -3 "$work/noisy.csv") "$work/fetch.csv" || fail "results 1, 2 differ through the noise"
  mon_corrupt=$(sed -n 's/.*results; \([0-9]*\) corrupt frames.*/\1/p' "$work/noisy.err")
  stop_board || fail "board did not exit cleanly"
  board_corrupt=$(sed -n 's/.*link: [0-9]* frames sent, [0-9]* received, \([0-9]*\) corrupt.*/\1/p' "$work/board.log")
  hit=$(sed -n 's/.*serial line: [0-9]* bytes, \([0-9]*\) hit by noise.*/\1/p' "$work/board.log")
  [ "${hit:-0}" -gt 0 ] || fail "the noise hit nothing"
  [ "${board_corrupt:-0}" -gt 0 ] || [ "${mon_corrupt:-0}" -gt 0 ] || fail "$hit bytes hit, no corrupt frame counted"
  pass "1 % line noise ($hit bytes hit; board counted $board_corrupt corrupt frames, the last fetch $mon_corrupt): result #3 = pitvol measure, log 1..3 whole"
  check_allocations # the link, log appends and GetResults streaming included
  ;;
*)
  echo "unknown case $case_name" >&2
  exit 2
  ;;
esac
exit 0
