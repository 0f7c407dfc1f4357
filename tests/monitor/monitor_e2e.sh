#!/usr/bin/env bash
# pitvol-monitor end to end over a pseudo-terminal, against pv-test-device
# (the real link, serial driver, result log, density and core with the
# board's state machine replaced). Label serial.
# usage: monitor_e2e.sh DEVICE MONITOR SYNTH PITVOL
set -euo pipefail
device=$1 monitor=$2 synth=$3 pitvol=$4
work=$(mktemp -d "${TMPDIR:-/tmp}/pv-monitor-e2e.XXXXXX")
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# start_device NAME ARGS...: runs a device, waits for its port link.
start_device() {
  local name=$1; shift
  "$device" --log "$work/$name-log" --port-link "$work/$name-port" --seconds 120 "$@" \
    >"$work/$name.out" 2>"$work/$name.err" &
  pids+=($!)
  for _ in $(seq 100); do [ -e "$work/$name-port" ] && return 0; sleep 0.05; done
  fail "device $name did not start: $(cat "$work/$name.err")"
}
mon() { "$monitor" "$@"; }

# 1. A clean line: hello, fetch, settings, a scan, refusals.
start_device clean --preload 20
port=$work/clean-port
mon "$port" hello | grep -q "results 1..20" || fail "hello"
mon "$port" fetch >"$work/fetch.csv" 2>/dev/null
[ "$(wc -l <"$work/fetch.csv")" -eq 21 ] || fail "fetch: want header + 20 rows"
[ "$(cut -d, -f1 "$work/fetch.csv" | tail -n +2 | tr '\n' ' ')" = "$(seq -s ' ' 1 20) " ] || fail "fetch ids"
# Result 7: volume 1500 + 1.25 * 6 cm3 (the device's synthetic results).
grep -q '^7,1790000420,PV_OK,polar,1507.5,30,150,' "$work/fetch.csv" || fail "fetch row 7"

# Live: commands typed into watch; it sees the scan's result as it happens.
printf 'set-mass 3000\nset-moisture 12.5\nstart\nstop\n' |
  mon "$port" watch --json --count 1 --seconds 20 >"$work/watch.json" || fail "watch exited with $?"
[ "$(grep -c '"type": "ack"' "$work/watch.json")" -eq 4 ] || fail "watch: want 4 acks ($(cat "$work/watch.json"))"
grep -q '"type": "result", "id": 21' "$work/watch.json" || fail "watch did not see result 21"
# Density of result 21: 3000 g over 1525 cm3 (+/- 30), w 12.5 %, reference 1850 kg/m3.
mon "$port" fetch --from 21 --json >"$work/r21.json" 2>/dev/null
# near FIELD VALUE: the JSON number within 1e-9 (relative) of VALUE.
near() {
  local v
  v=$(sed -n "s/.*\"$1\": \([^,}]*\).*/\1/p" "$work/r21.json")
  awk -v a="$v" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a != "" && d <= 1e-9 * b) }' \
    || fail "result 21: $1 = $v, want $2"
}
near volume_cm3 1525
near wet_kg_m3 1967.2131147541      # 3000 g / 1525 cm3 = 120000/61 g/cm3... x 1000
near wet_low_kg_m3 1929.2604501608  # 3000 / 1555
near wet_high_kg_m3 2006.6889632107 # 3000 / 1495
near dry_kg_m3 1748.6338797814      # wet / 1.125
near compaction_percent 94.520750258455  # dry / 1850
# The warning bits decoded from the core's table: result 22 (even: 3 % of
# the volume bridged, and thinned) as text; never a bare bit mask.
printf 'start\nstop\n' | mon "$port" watch --count 1 --seconds 20 >"$work/watch22.txt" || fail "watch 22"
grep -q '^result   #22 .*, warnings: unseen wall bridged$' "$work/watch22.txt" \
  || fail "result 22: warnings not decoded ($(cat "$work/watch22.txt"))"
grep -q '^         warning: part of the wall was not seen' "$work/watch22.txt" || fail "result 22: no sentence"
grep -q '^         notes: dense bins thinned$' "$work/watch22.txt" || fail "result 22: no notes"
grep -q '0x' "$work/watch22.txt" && fail "result 22: a bare warning mask"
mon "$port" fetch --from 21 --json >"$work/r2122.json" 2>/dev/null
grep -q '"id": 21, .*"warnings": \[\], "notes": \["dense parts of the scan were thinned' "$work/r2122.json" \
  || fail "result 21 JSON: thinning is a note ($(cat "$work/r2122.json"))"
mon "$port" fetch --from 22 >"$work/r22.csv" 2>/dev/null
tail -1 "$work/r22.csv" | grep -q ',PV_WARN_POINTS_THINNED PV_WARN_BRIDGED,' || fail "result 22 CSV: $(tail -1 "$work/r22.csv")"
# The test record: result 23 (1527.5 +/- 30 cm3, 3000 g, 12.5 %, 1850
# kg/m3: compaction 94.4 %, 92.6 .. 96.2) against 95 %: UNDECIDED, with the
# interval that would decide, 1527.5 - 1527.5 x 94.366 / 95 = 10.19 cm3.
for c in "set-test-id FDT-0023" "set-operator J. Okafor" "set-required-compaction 95" "set-mass 3000" \
         "set-moisture 12.5"; do
  mon "$port" $c >/dev/null 2>"$work/rec.err" || fail "$c: $(cat "$work/rec.err")"
done
mon "$port" set-location "STA 1+250, 2.5 m LT, lift 3" >/dev/null || fail "set-location"
printf 'start\nstop\n' | mon "$port" watch --count 1 --seconds 20 >"$work/watch23.txt" || fail "watch 23"
grep -q '^         test FDT-0023, STA 1+250, 2.5 m LT, lift 3, operator J. Okafor$' "$work/watch23.txt" \
  || fail "result 23: no record line ($(cat "$work/watch23.txt"))"
grep -q '^         verdict  UNDECIDED (required 95.0 %): the range straddles it; a volume interval under +/- 10.2 cm3 would decide$' \
  "$work/watch23.txt" || fail "result 23: verdict ($(cat "$work/watch23.txt"))"
mon "$port" fetch --from 23 --json >"$work/r23.json" 2>/dev/null
grep -q '"test_id": "FDT-0023", "location": "STA 1+250, 2.5 m LT, lift 3", "operator": "J. Okafor", "required_compaction_percent": 95, "verdict": "UNDECIDED", "decides_within_cm3": 10.1' \
  "$work/r23.json" || fail "result 23 JSON: $(cat "$work/r23.json")"
mon "$port" fetch --from 23 >"$work/r23.csv" 2>/dev/null
head -1 "$work/r23.csv" | grep -q ',test_id,location,operator,required_compaction_percent,verdict,decides_within_cm3$' \
  || fail "CSV header without the record"
tail -1 "$work/r23.csv" | grep -q ',FDT-0023,"STA 1+250, 2.5 m LT, lift 3",J. Okafor,95,UNDECIDED,10.1' \
  || fail "result 23 CSV: $(tail -1 "$work/r23.csv")"
# The test id was used up by result 23; the next result has none.
printf 'start\nstop\n' | mon "$port" watch --json --count 1 --seconds 20 >"$work/watch24.json" || fail "watch 24"
grep -q '"id": 24, .*"test_id": "", "location": "STA 1+250' "$work/watch24.json" || fail "test id not used up"
# Absurd numbers refused by the board, with the range; a hex number by the monitor.
for c in "set-mass 1e308" "set-mass 1e-300" "set-required-compaction 400" "set-max-dry-density 1.85"; do
  set +e; mon "$port" $c 2>"$work/rec.err"; rc=$?; set -e
  [ $rc -eq 1 ] && grep -q "is outside" "$work/rec.err" || fail "$c: exit $rc, $(cat "$work/rec.err")"
done
set +e; mon "$port" set-mass 0x10 2>"$work/rec.err"; rc=$?; set -e
[ $rc -eq 2 ] && [ "$(wc -l <"$work/rec.err")" -eq 1 ] || fail "set-mass 0x10: exit $rc, $(cat "$work/rec.err")"
# Refusals: exit status 1 and a reason.
set +e
mon "$port" set-mass -5 2>"$work/nack.err"; rc=$?
set -e
[ $rc -eq 1 ] || fail "negative mass: exit $rc, want 1"
grep -q "outside 50 .. 100000 g" "$work/nack.err" || fail "negative mass: no reason"
set +e
mon "$port" stop 2>/dev/null; rc=$?
set -e
[ $rc -eq 1 ] || fail "stop while idle: exit $rc, want 1"

# 2. Line noise, 1 % of bytes both ways: every result still arrives.
start_device noisy --preload 30 --noise 1 --seed 7
mon "$work/noisy-port" fetch --retry-ms 200 --tries 50 >"$work/noisy.csv" 2>"$work/noisy.err" \
  || fail "noisy fetch: $(cat "$work/noisy.err")"
[ "$(cut -d, -f1 "$work/noisy.csv" | tail -n +2 | tr '\n' ' ')" = "$(seq -s ' ' 1 30) " ] \
  || fail "noisy fetch ids: $(cut -d, -f1 "$work/noisy.csv" | tr '\n' ' ')"
cmp <(cut -d, -f1-11 "$work/noisy.csv" | head -21) <(cut -d, -f1-11 "$work/fetch.csv") \
  || fail "noisy rows differ from clean ones"
corrupt=$(sed -n 's/.*results; \([0-9]*\) corrupt frames.*/\1/p' "$work/noisy.err")
[ "${corrupt:-0}" -gt 0 ] || fail "noise did not hit any frame"
echo "noisy fetch: 30 results, $corrupt corrupt frames counted by the monitor"
# Commands through the noise: repeated until answered, done once each (a
# repeated StopScan must not be refused, nor make a second result).
for c in "set-mass 2500" start stop; do
  mon "$work/noisy-port" $c --retry-ms 200 --tries 50 >/dev/null 2>"$work/noisy-cmd.err" \
    || fail "noisy $c: $(cat "$work/noisy-cmd.err")"
done
# The board answers StopScan first and logs the result just after: ask
# until result 31 is there (at most 50 times).
for _ in $(seq 50); do
  mon "$work/noisy-port" fetch --from 25 --retry-ms 200 --tries 50 >"$work/noisy2.csv" 2>/dev/null \
    || fail "noisy fetch after the scan"
  grep -q '^31,' "$work/noisy2.csv" && break
  sleep 0.1
done
[ "$(cut -d, -f1 "$work/noisy2.csv" | tail -n +2 | tr '\n' ' ')" = "$(seq -s ' ' 25 31) " ] \
  || fail "noisy scan: want results 25..31 ($(cut -d, -f1 "$work/noisy2.csv" | tr '\n' ' '))"
grep -q '^31,.*,2500,' "$work/noisy2.csv" || fail "noisy scan: result 31 lacks the mass"

# A record the board cannot give (damaged storage): the rest arrives, the
# gap is named, the exit status says it is incomplete.
start_device damaged --preload 8 --lose-id 5
set +e
mon "$work/damaged-port" fetch >"$work/damaged.csv" 2>"$work/damaged.err"; rc=$?
set -e
[ $rc -eq 1 ] || fail "damaged log: exit $rc, want 1"
[ "$(cut -d, -f1 "$work/damaged.csv" | tail -n +2 | tr '\n' ' ')" = "1 2 3 4 6 7 8 " ] || fail "damaged log rows"
grep -q "ids 5 .. 5" "$work/damaged.err" || fail "damaged log: gap not named ($(cat "$work/damaged.err"))"

# 3. A real scan: the board's result equals pitvol measure on the same file.
"$synth" "$work/pit.ply" --points 60000 --seed 3 >/dev/null
want=$("$pitvol" measure "$work/pit.ply" --json | sed -n 's/.*"volume_cm3": \([^,}]*\).*/\1/p')
[ -n "$want" ] || fail "pitvol measure gave no volume"
start_device scan --scan "$work/pit.ply"
printf 'start\nstop\n' | mon "$work/scan-port" watch --json --count 1 --seconds 100 >"$work/scan.json" \
  || fail "scan watch"
got=$(sed -n 's/.*"type": "result".*"volume_cm3": \([^,}]*\).*/\1/p' "$work/scan.json")
[ "$got" = "$want" ] || fail "monitor volume $got != pitvol measure $want"
echo "scan: monitor and pitvol measure agree: $got cm3"

# 4. A scan that cannot be measured: the result says why and an Error follows.
"$synth" "$work/tiny.ply" --points 20 --seed 3 >/dev/null
start_device bad --scan "$work/tiny.ply"
printf 'start\nstop\n' | mon "$work/bad-port" watch --json --seconds 2 >"$work/bad.json" || fail "bad watch"
grep -q '"type": "result", "id": 1, .*"status": "PV_ERR_[A-Z_]*", .*"volume_cm3": null' "$work/bad.json" \
  || fail "failed scan: no result with an error status ($(cat "$work/bad.json"))"
grep -q '"type": "error", "code": [1-9][0-9]*, "name": "PV_ERR_' "$work/bad.json" || fail "failed scan: no Error"

# 4b. Not a pit (a closed sphere shell, radius 150 mm, on a golden-angle
# spiral): the result names the plausibility check that refused it, with the
# figure it measured and its limit, the same bits as pitvol measure --json
# on the same file; in the watch text, the JSON and the CSV.
awk 'BEGIN { n = 60000; for (i = 0; i < n; i++) { z = 1 - 2 * (i + 0.5) / n; r = sqrt(1 - z * z);
  t = 2.39996322972865332 * i; printf "%.4f %.4f %.4f\n", 150 * r * cos(t), 150 * r * sin(t), 150 * z } }' \
  >"$work/sphere.xyz"
"$pitvol" measure "$work/sphere.xyz" --json >"$work/sphere-cli.json" 2>/dev/null && fail "pitvol measure measured a sphere"
field() { sed -n "s/.*\"$1\": \([^,}]*\).*/\1/p" "$2"; }
want_value=$(field check_value "$work/sphere-cli.json") want_limit=$(field check_limit "$work/sphere-cli.json")
grep -q '"failed_check": "PV_PIT_CHECK_NARROW_MOUTH"' "$work/sphere-cli.json" \
  || fail "pitvol measure: the sphere not refused by the mouth check ($(cat "$work/sphere-cli.json"))"
start_device sphere --scan "$work/sphere.xyz"
printf 'start\nstop\n' | mon "$work/sphere-port" watch --json --count 1 --seconds 60 >"$work/sphere.json" \
  || fail "sphere watch"
grep '"type": "result"' "$work/sphere.json" >"$work/sphere-result.json" || fail "sphere: no result"
grep -q '"status": "PV_ERR_NOT_A_PIT", .*"volume_cm3": null, .*"failed_check": "PV_PIT_CHECK_NARROW_MOUTH"' \
  "$work/sphere-result.json" || fail "sphere: result without its check ($(cat "$work/sphere-result.json"))"
[ "$(field check_value "$work/sphere-result.json")" = "$want_value" ] \
  && [ "$(field check_limit "$work/sphere-result.json")" = "$want_limit" ] \
  || fail "sphere: figures $(field check_value "$work/sphere-result.json") / $(field check_limit "$work/sphere-result.json"), pitvol measure $want_value / $want_limit"
mon "$work/sphere-port" fetch >"$work/sphere.csv" 2>/dev/null || fail "sphere fetch csv"
head -1 "$work/sphere.csv" | grep -q ',failed_check,check_value,check_limit,gap_from_mm,gap_to_mm,warning_names,' \
  || fail "CSV header without the refusal columns"
tail -1 "$work/sphere.csv" | grep -q ",PV_PIT_CHECK_NARROW_MOUTH,[0-9.e-]*,0.5,,,[A-Z_ ]*," \
  || fail "sphere: CSV row $(tail -1 "$work/sphere.csv")"
printf 'start\nstop\n' | mon "$work/sphere-port" watch --count 1 --seconds 60 >"$work/sphere.txt" \
  || fail "sphere watch (text)"
grep -q "no measurement: PV_ERR_NOT_A_PIT (PV_PIT_CHECK_NARROW_MOUTH: rim section / widest section [0-9.]* (an open pit: at least 0.50))" \
  "$work/sphere.txt" || fail "sphere: text without its check ($(cat "$work/sphere.txt"))"
echo "sphere: refused by the mouth check, figure $want_value (limit $want_limit) as pitvol measure"

# 4c. A device whose strings carry terminal control sequences (clear the
# screen, retitle the window, 8-bit CSI, bytes that are not UTF-8): the
# monitor's text never passes a control byte to the terminal, it shows
# them escaped; JSON escapes them as JSON does.
start_device hostile --preload 2 --hostile
ctl() { LC_ALL=C grep -c $'[\x01-\x08\x0b-\x1f\x7f\x9b]' "$1" || true; }
mon "$work/hostile-port" hello >"$work/hostile-hello.txt" || fail "hostile hello"
[ "$(ctl "$work/hostile-hello.txt")" = 0 ] || fail "hello passed control bytes: $(od -c "$work/hostile-hello.txt" | head)"
grep -qF 'device \x1b[2J\x1b]0;owned\x07\x9b31m\u009b1m\xff, protocol' "$work/hostile-hello.txt" \
  || fail "hello: the device id not shown escaped ($(cat "$work/hostile-hello.txt"))"
LC_ALL=C grep -q $'\xc2\x9b' "$work/hostile-hello.txt" && fail "hello passed a UTF-8 C1 control"
set +e
mon "$work/hostile-port" stop 2>"$work/hostile-nack.txt"; rc=$?
set -e
[ $rc -eq 1 ] || fail "hostile stop while idle: exit $rc"
[ "$(ctl "$work/hostile-nack.txt")" = 0 ] || fail "a refusal passed control bytes"
grep -qF 'refused: \x1b[2J' "$work/hostile-nack.txt" || fail "refusal not escaped: $(cat "$work/hostile-nack.txt")"
printf 'start\nstop\n' | mon "$work/hostile-port" watch --count 1 --seconds 20 >"$work/hostile-watch.txt" 2>&1 \
  || fail "hostile watch"
[ "$(ctl "$work/hostile-watch.txt")" = 0 ] || fail "watch passed control bytes: $(od -c "$work/hostile-watch.txt" | head -20)"
grep -qF 'po\x1b[8mlar, volume' "$work/hostile-watch.txt" || fail "method not escaped: $(cat "$work/hostile-watch.txt")"
mon "$work/hostile-port" fetch >"$work/hostile.csv" 2>/dev/null || fail "hostile fetch"
[ "$(ctl "$work/hostile.csv")" = 0 ] || fail "CSV passed control bytes"
mon "$work/hostile-port" hello --json >"$work/hostile.json" || fail "hostile hello json"
[ "$(ctl "$work/hostile.json")" = 0 ] || fail "JSON passed control bytes"
grep -qF '"device_id": "\u001b[2J' "$work/hostile.json" || fail "JSON: $(cat "$work/hostile.json")"
echo "hostile device: every string escaped"

# 5. A board whose clock was never set (1970, no RTC): its results carry
# time 0, which the monitor shows as clock-not-set, not as a 1970 date.
start_device noclock --preload 2 --clock 0
mon "$work/noclock-port" fetch --json >"$work/noclock.json" 2>/dev/null || fail "noclock fetch"
[ "$(grep -c '"time_utc": "clock-not-set"' "$work/noclock.json")" -eq 2 ] \
  || fail "unset clock: want 2 results with clock-not-set ($(cat "$work/noclock.json"))"
grep -q '1970' "$work/noclock.json" && fail "unset clock shown as a 1970 date"
mon "$work/noclock-port" fetch >"$work/noclock.csv" 2>/dev/null || fail "noclock fetch csv"
[ "$(cut -d, -f2 "$work/noclock.csv" | tail -n +2 | tr '\n' ' ')" = "0 0 " ] || fail "unset clock: CSV time"
echo "PASS"
