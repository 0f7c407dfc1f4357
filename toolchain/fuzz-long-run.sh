#!/usr/bin/env bash
# The long fuzz runs of docs/reliability.md, resumable: run one harness for
# a while from its own growing corpus, then record what the run did.
#
#   toolchain/fuzz-long-run.sh NAME SECONDS [SEED]
#   toolchain/fuzz-long-run.sh --total NAME
#
# NAME is a harness of fuzz/CMakeLists.txt (fuzz_session, fuzz_usb_stream,
# ...). The run starts from the harness's output corpus in
# $PV_FUZZ_DIR/NAME (default build-fuzz/long; libFuzzer reads it back first,
# so a run goes on where the last one stopped) and the committed seeds, at
# nice 19, and stops after SECONDS or at 10 M executions. Each run appends
# one line to $PV_FUZZ_DIR/NAME.runs (UTC start, commit, seed, executions,
# seconds, edges, features, exit status); --total adds the executions up.
# A crash, leak, timeout or invariant failure leaves its input in
# $PV_FUZZ_DIR/NAME-* and exits non-zero: copy it into fuzz/corpus/ as a
# regression seed, then fix it.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${PV_FUZZ_DIR:-build-fuzz/long}

if [ "${1:-}" = "--total" ]; then
  [ $# -eq 2 ] || { echo "usage: $0 --total NAME" >&2; exit 2; }
  runs="$dir/$2.runs"
  [ -f "$runs" ] || { echo "$0: no runs recorded in $runs" >&2; exit 1; }
  awk '{ n += $4; s += $5 } END { printf "%d runs, %d executions in %d s\n", NR, n, s }' "$runs"
  exit 0
fi
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: $0 NAME SECONDS [SEED] | $0 --total NAME" >&2
  exit 2
fi
name=$1 seconds=$2 seed=${3:-$(date +%s)}

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target "$name" >/dev/null
# The harness's corpus and input size, as CTest runs it (fuzz/CMakeLists.txt).
# (ctest's listing is read whole first: grep -m1 on the pipe could stop
# ctest with SIGPIPE, which pipefail reports as no such test.)
listing=$(ctest --preset fuzz -N -V -R "^${name}\$")
spec=$(grep -m1 -- "-max_len=" <<<"$listing") ||
  { echo "$0: no fuzz test named $name" >&2; exit 2; }
max_len=$(sed -n 's/.*-max_len=\([0-9]*\).*/\1/p' <<<"$spec")
corpus=$(awk '{ print $NF }' <<<"$spec" | tr -d '"')

mkdir -p "$dir/$name"
log="$dir/$name.log"
start=$(date -u +%Y-%m-%dT%H:%M:%SZ)
commit=$(git rev-parse --short HEAD)  # the build's, read before the run
rc=0
nice -n 19 "build-fuzz/fuzz/$name" -runs=10000000 -max_total_time="$seconds" -seed="$seed" \
  -max_len="$max_len" -timeout=120 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$dir/$name-" "$dir/$name" "$corpus" >"$log" 2>&1 || rc=$?

# libFuzzer's final statistics and its last status line (edges, features).
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
last=$(tr '\r' '\n' <"$log" | grep -E '^#[0-9]+' | tail -1 || true)
cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
secs=$(( $(date -u +%s) - $(date -u -d "$start" +%s) ))
echo "$start $commit $seed ${execs:-0} $secs ${cov:-0} ${ft:-0} $rc" >>"$dir/$name.runs"
echo "$name: ${execs:-0} executions in $secs s (edges ${cov:-?}, features ${ft:-?}), exit $rc; log $log"
"$0" --total "$name"
exit "$rc"
