#!/usr/bin/env bash
# Size report per target: the core library (text, data, bss: GNU size over
# its objects), the MCU app image, and the session block (pv_session_size)
# for the default and the MCU configuration, each measured on its target
# (the board's under qemu-aarch64, the MCU's under qemu-system-arm).
# Needs the default, board and mcu presets built (tests/run-tests.sh).
#   toolchain/size-report.sh            print the markdown table
#   toolchain/size-report.sh --write    also replace it in docs/memory.md
set -euo pipefail
cd "$(dirname "$0")/.."

lib_size() {  # SIZE-TOOL LIB -> "text data bss"
  "$1" -t "$2" | awk '/\(TOTALS\)/ {print $1, $2, $3}'
}
fmt() { sed ':a;s/\B[0-9]\{3\}\>/,&/;ta' <<<"$1"; }  # 1234567 -> 1,234,567
block_of() {  # CMD... -> bytes
  "$@" | awk '/^block_bytes/ {print $2}'
}
mcu_run() {  # ARGS... -> the MCU app's output under qemu
  local args="enable=on,target=native,arg=pv-replay"
  for a in "$@"; do args+=",arg=$a"; done
  qemu-system-arm -M mps2-an500 -nographic -monitor none -serial none \
    -semihosting-config "$args" -kernel build-mcu/bin/pitvol-mcu.elf
}
# As the board preset's tests run it: through the sysroot's loader
# (toolchain/aarch64-linux-gnu.cmake).
sysroot=${PITVOL_ARM64_SYSROOT:-build-sysroot/arm64}/tree
qemu_a64=(qemu-aarch64-static "$sysroot/lib/ld-linux-aarch64.so.1"
          --library-path "$sysroot/usr/lib/aarch64-linux-gnu")

for f in build/core/libpitvol_core.a build-board/core/libpitvol_core.a \
         build-mcu/core/libpitvol_core.a build-mcu/bin/pitvol-mcu.elf \
         build/bin/pitvol-replay build-board/bin/pitvol-replay; do
  [ -f "$f" ] || { echo "missing $f: build the default, board and mcu presets first" >&2; exit 1; }
done

table=$(
  echo "| target | core text | core data | core bss | block, default config | block, MCU config |"
  echo "|---|---|---|---|---|---|"
  read -r t d b <<<"$(lib_size size build/core/libpitvol_core.a)"
  echo "| host x86-64 (\`default\`) | $(fmt "$t") | $(fmt "$d") | $(fmt "$b") | $(fmt "$(block_of build/bin/pitvol-replay --block-size)") | $(fmt "$(block_of build/bin/pitvol-replay --mcu-config --block-size)") |"
  read -r t d b <<<"$(lib_size aarch64-linux-gnu-size build-board/core/libpitvol_core.a)"
  echo "| board aarch64 (\`board\`) | $(fmt "$t") | $(fmt "$d") | $(fmt "$b") | $(fmt "$(block_of "${qemu_a64[@]}" build-board/bin/pitvol-replay --block-size)") | $(fmt "$(block_of "${qemu_a64[@]}" build-board/bin/pitvol-replay --mcu-config --block-size)") |"
  read -r t d b <<<"$(lib_size arm-none-eabi-size build-mcu/core/libpitvol_core.a)"
  echo "| MCU Cortex-M7 (\`mcu\`) | $(fmt "$t") | $(fmt "$d") | $(fmt "$b") | $(fmt "$(block_of mcu_run --block-size)") | $(fmt "$(block_of mcu_run --mcu-config --block-size)") |"
  echo
  read -r t d b <<<"$(arm-none-eabi-size build-mcu/bin/pitvol-mcu.elf | awk 'NR==2 {print $1, $2, $3}')"
  blk=$(arm-none-eabi-size -A build-mcu/bin/pitvol-mcu.elf | awk '$1==".pv_block" {print $2}')
  echo "MCU test app \`pitvol-mcu.elf\` (core + newlib stdio + semihosting): text $(fmt "$t") B, data $(fmt "$d") B, bss $(fmt "$b") B, of which the session block region \`.pv_block\` $(fmt "$blk") B."
)
echo "$table"

if [ "${1:-}" = "--write" ]; then
  doc=docs/memory.md
  begin='<!-- size-report: begin (toolchain/size-report.sh --write) -->'
  end='<!-- size-report: end -->'
  grep -qF "$begin" "$doc" || { echo "no size-report markers in $doc" >&2; exit 1; }
  awk -v b="$begin" -v e="$end" -v t="$table" '
    $0 == b {print; print t; skip = 1; next}
    $0 == e {skip = 0}
    !skip {print}' "$doc" > "$doc.tmp"
  mv "$doc.tmp" "$doc"
  echo "wrote $doc"
fi
