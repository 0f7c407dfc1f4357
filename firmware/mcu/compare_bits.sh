#!/usr/bin/env bash
# Same bits on two targets: runs pv-replay on the same scans natively
# (reference) and on a target (under its emulator), and diffs every result
# field's bits. Lines starting with '#' (decimal values for people) are
# not compared.
# Usage: compare_bits.sh OUTDIR "REFERENCE CMD" "TARGET CMD" SCAN...
#   A TARGET CMD "semihost:QEMU ARGS -kernel APP.elf APP ARGS" runs a
#   bare-metal app once per scan, its arguments passed through semihosting.
set -euo pipefail
out=$1 ref_cmd=$2 target_cmd=$3
shift 3
mkdir -p "$out"
for scan in "$@"; do
  [ -f "$scan" ] || { echo "FAIL: missing scan $scan (run the default preset's tests first: they generate the corpus)" >&2; exit 1; }
done
ref_bin=${ref_cmd%% *}
[ -x "$ref_bin" ] || { echo "FAIL: no reference $ref_bin (build the default preset first)" >&2; exit 1; }

start=$(date +%s)
# shellcheck disable=SC2086
$ref_cmd "$@" > "$out/reference.txt"
ref_s=$(( $(date +%s) - start ))

start=$(date +%s)
if [[ $target_cmd == semihost:* ]]; then
  read -r -a words <<<"${target_cmd#semihost:}"
  qemu=() app_args=() seen_kernel=0 after=0
  for w in "${words[@]}"; do
    if [ $after -eq 1 ]; then app_args+=("$w"); continue; fi
    qemu+=("$w")
    if [ $seen_kernel -eq 1 ]; then after=1; fi
    if [ "$w" = "-kernel" ]; then seen_kernel=1; fi
  done
  # One run per scan, from the scan's directory: newlib reads the command
  # line into a 255-byte buffer, too small for several absolute paths.
  : > "$out/target.txt"
  for scan in "$@"; do
    sh_args="enable=on,target=native,arg=pv-replay"
    for a in "${app_args[@]}" "$(basename "$scan")"; do sh_args+=",arg=$a"; done
    (cd "$(dirname "$scan")" && "${qemu[@]}" -semihosting-config "$sh_args") >> "$out/target.txt" || true
  done
else
  # shellcheck disable=SC2086
  $target_cmd "$@" > "$out/target.txt" || true
fi
target_s=$(( $(date +%s) - start ))

grep -v '^#' "$out/reference.txt" > "$out/reference.bits"
grep -v '^#' "$out/target.txt" | tr -d '\r' > "$out/target.bits"
scans=$(grep -c '^scan ' "$out/reference.bits" || true)
if [ "$scans" -ne $# ]; then
  echo "FAIL: the reference measured $scans of $# scans" >&2
  cat "$out/reference.txt" >&2
  exit 1
fi
if ! diff -u "$out/reference.bits" "$out/target.bits" > "$out/diff.txt"; then
  echo "FAIL: result bits differ between the reference and the target ($out/diff.txt):" >&2
  head -40 "$out/diff.txt" >&2
  grep '^#' "$out/target.txt" >&2 || true
  exit 1
fi
grep '^# status' "$out/reference.txt"
echo "ok: $scans scans, every result field bit-identical (reference ${ref_s}s, target ${target_s}s)"
