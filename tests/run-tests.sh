#!/usr/bin/env bash
# Every test: install what is missing, build the Release preset and run all
# CTest labels (unit, corpus), then the Debug preset with ASan + UBSan and
# run the unit tests there; then the board (aarch64, under qemu-aarch64) and
# MCU (Cortex-M7, under qemu-system-arm) builds, their tests and the
# same-bits comparison with the Release build (docs/targets.md).
set -euo pipefail
cd "$(dirname "$0")/.."
toolchain/install-deps.sh --cross
jobs=$(nproc)

cmake --preset default >/dev/null
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs"

cmake --preset debug >/dev/null
cmake --build --preset debug -j "$jobs"
ctest --preset debug -j "$jobs" -L unit

# Board and MCU: after the Release tests, which generate the corpus scans
# the bits tests replay.
cmake --preset board >/dev/null
cmake --build --preset board -j "$jobs"
ctest --preset board -j "$jobs" -L 'unit|bits'
cmake --preset mcu >/dev/null
cmake --build --preset mcu -j "$jobs"
ctest --preset mcu -j "$jobs" -L mcu
toolchain/run-cppcheck.sh
toolchain/size-report.sh   # docs/memory.md: refresh with --write
