#!/usr/bin/env bash
# The simulator gives the same scan, byte for byte, on every x86-64 CPU:
# one scan made natively (Embree's best kernels, glibc's libm for this CPU)
# against the same scan with Embree capped at SSE2 and at AVX2, and under
# qemu-x86_64 emulating CPUs without AVX or FMA (Embree's SSE2 kernels,
# glibc's libm without FMA), one of each vendor.
# Usage: sim_same_bits.sh PITVOL_SIM WORK_DIR QEMU_X86_64|-
set -euo pipefail
sim=$1 work=$2 qemu=$3
rm -rf "$work" && mkdir -p "$work"
scan=(scan --family hand_dug --seed 3 --points 30000)
"$sim" "${scan[@]}" --out "$work/native" >/dev/null
status=0
same() {  # name: compares work/name.* with the native scan
  local ok=1
  for ext in ply frames; do  # the .json names its own file
    if ! cmp -s "$work/native.$ext" "$work/$1.$ext"; then
      echo "FAIL: $1.$ext differs from the native scan" >&2
      ok=0 status=1
    fi
  done
  [ $ok -eq 0 ] || echo "same bits: $1"
}
for isa in sse2 avx2; do
  PITVOL_SIM_ISA=$isa "$sim" "${scan[@]}" --out "$work/embree-$isa" >/dev/null
  same "embree-$isa"
done
if [ "$qemu" != "-" ]; then
  for cpu in qemu64 Conroe; do  # AMD-flavoured SSE2; Intel Core 2 (SSSE3)
    "$qemu" -cpu "$cpu" "$sim" "${scan[@]}" --out "$work/cpu-$cpu" >/dev/null
    same "cpu-$cpu"
  done
fi
exit $status
