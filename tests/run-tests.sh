#!/usr/bin/env bash
# Every test: install what is missing, build the Release preset and run all
# CTest labels (unit, corpus), then the Debug preset with ASan + UBSan and
# run the unit tests there.
set -euo pipefail
cd "$(dirname "$0")/.."
toolchain/install-deps.sh
jobs=$(nproc)

cmake --preset default >/dev/null
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs" -LE peers  # label peers: minutes a scan, run by hand

cmake --preset debug >/dev/null
cmake --build --preset debug -j "$jobs"
ctest --preset debug -j "$jobs" -L unit
