#!/usr/bin/env bash
# The envelope table in one command (docs/accuracy.md, "The envelope
# sweeps"): makes the sweep unless it is there, measures every scan with
# the built pitvol and prints the table; --write-doc puts it in
# docs/accuracy.md between the envelope-table markers.
#
#   host_tools/accuracy/envelope.sh [--seed S] [--count N] [--out DIR]
#       [--jobs N] [--peers grid25,cloudcompare,poisson] [--config FILE]
#       [--write-doc]
# --config: pitvol measure's configuration (a loosened limit, say), passed
# to every measurement and named in the table.
#
# Seeds below 1000 are tuning seeds, 1000 and up fresh (held out). Default:
# seed 1, 300 scans, build/envelope-s<S>-n<N>, 2 jobs (the sweep is made in
# that many parts, cases --from I, then joined). Needs the Release build
# (cmake --preset default && cmake --build --preset default).
set -euo pipefail
cd "$(dirname "$0")/../.."
seed=1 count=300 out="" jobs=2 peers="" config="" write_doc=0
while [ $# -gt 0 ]; do
  case $1 in
    --seed) seed=$2; shift 2 ;;
    --count) count=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --peers) peers=$2; shift 2 ;;
    --config) config=$2; shift 2 ;;
    --write-doc) write_doc=1; shift ;;
    *) echo "usage: $0 [--seed S] [--count N] [--out DIR] [--jobs N] [--peers LIST] [--config FILE] [--write-doc]" >&2; exit 2 ;;
  esac
done
out=${out:-build/envelope-s$seed-n$count}
bin=build/bin
[ -x $bin/pitvol-sim ] && [ -x $bin/pitvol-accuracy ] || { echo "$0: build first (cmake --build --preset default)" >&2; exit 2; }
args="sweep --seed $seed --count $count"
if [ ! -f "$out/manifest.csv" ] || [ "$(cat "$out/sweep-args" 2>/dev/null)" != "$args" ]; then
  rm -rf "$out" && mkdir -p "$out"
  start=$(date +%s)
  per=$(( (count + jobs - 1) / jobs )) pids=()
  for ((k = 0; k < jobs && k * per < count; ++k)); do
    n=$(( count - k * per < per ? count - k * per : per ))
    $bin/pitvol-sim sweep --seed "$seed" --from $((k * per)) --count $n --out "$out/part-$k" \
      2> >(grep -v '^pitvol-sim: s' >&2) &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p"; done
  # One sweep again: the files side by side, the manifests end to end.
  parts=$(ls -d "$out"/part-* | sort -t- -k2 -n)
  head -1 "$out/part-0/manifest.csv" > "$out/manifest.csv"
  for d in $parts; do
    tail -n +2 "$d/manifest.csv" >> "$out/manifest.csv"
    mv "$d"/*.ply "$out/"
  done
  { echo "["; for d in $parts; do sed '1d;$d' "$d/manifest.json" | sed '$!b; s/$/,/'; done | sed '$ s/,$//'; echo "]"; } \
    > "$out/manifest.json"
  rm -rf "$out"/part-*
  echo "$args" > "$out/sweep-args"
  echo "generated $count scans in $(( $(date +%s) - start )) s" >&2
fi
kind=tuning
[ "$seed" -ge 1000 ] && kind=fresh
# The last commit that changed the core (what the table measures).
commit=$(git log -1 --format=%h -- core 2>/dev/null || echo unknown)
title="Envelope ($kind seeds, core at $commit)"
start=$(date +%s)
table=$($bin/pitvol-accuracy "$out" --envelope --markdown --jobs "$jobs" --title "$title" \
        ${peers:+--peers "$peers"} ${config:+--config "$config"})
echo "measured in $(( $(date +%s) - start )) s" >&2
cmd="host_tools/accuracy/envelope.sh --seed $seed --count $count${peers:+ --peers $peers}${config:+ --config $config}"
block=$(printf '%s\n\nMade by `%s` (%s).\n' "$table" "$cmd" "$(date -u +%Y-%m-%d)")
if [ $write_doc -eq 1 ]; then
  doc=docs/accuracy.md
  grep -q '^<!-- envelope-table:begin -->$' $doc || { echo "$0: no envelope-table markers in $doc" >&2; exit 3; }
  BLOCK="$block" /usr/bin/python3 - "$doc" <<'PY'
import os, re, sys
p = sys.argv[1]
s = open(p).read()
a, b = '<!-- envelope-table:begin -->\n', '<!-- envelope-table:end -->'
i, j = s.index(a) + len(a), s.index(b)
open(p, 'w').write(s[:i] + os.environ['BLOCK'] + '\n' + s[j:])
PY
  echo "wrote the table into $doc" >&2
else
  printf '%s\n' "$block"
fi
