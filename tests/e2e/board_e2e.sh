#!/usr/bin/env bash
# End-to-end tests of the board application (label e2e): pitvol-board-emu
# (the same code as pitvol-board, the real libusb driver, the scanner
# emulated on umockdev, the PNG display) driven through its button pipe.
# Assertions read what the screens laid out (DIR/<screen>.txt and
# DIR/screens.log, written beside the PNGs) and the board's log; the
# reference volume comes from `pitvol measure` on the same scan's PLY.
#
#   board_e2e.sh CASE BIN_DIR FIXTURE_DIR WORK_DIR
# CASE: full_scan | stop_mid_scan | unplug_idle | unplug_replug | unplug_end | no_scanner_at_start | refused
set -uo pipefail
case_name=$1 bin=$2 fixtures=$3 work=$4/$1

command -v umockdev-wrapper >/dev/null || { echo "SKIP: umockdev-wrapper not installed"; exit 77; }

fail() { echo "FAIL [$case_name]: $*" >&2; [ -f "$work/board.log" ] && sed 's/^/  log: /' "$work/board.log" | grep -v "event tick" | tail -30 >&2; stop_board; exit 1; }
pass() { echo "ok   [$case_name]: $*"; }

rm -rf "$work"
mkdir -p "$work"
pipe=$work/buttons
screens=$work/screens
pid=

start_board() { # frames file, then pitvol-board-emu options
  "$bin/pitvol-board-emu" "$@" --display "png:$screens" --input "pipe:$pipe" \
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
  until [ "$(grep -Ec -- "$1" "$work/board.log" 2>/dev/null)" -ge "$n" ]; do
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
  json=$("$bin/pitvol" measure "$@" --json 2>/dev/null)
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
  # The counter is live: estimate/finish's kd-tree scratch is seen.
  grep -Eq "measure=[1-9]" <<<"$line" || fail "the allocation counter saw nothing: $line"
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
  grep -q "^text .*|too little wall seen" "$screens/refused.txt" || [ "$ref_st" != PV_ERR_TOO_FEW_LAYERS ] ||
    fail "reason not shown"
  pass "refused with $ref_st, as pitvol measure"
  stop_board || fail "board did not exit cleanly"
  png_ok refused
  ;;
*)
  echo "unknown case $case_name" >&2
  exit 2
  ;;
esac
exit 0
