#!/usr/bin/env bash
# Every test: install what is missing, build the Release preset and run all
# CTest labels (unit, corpus, usb, cli), then the Debug preset with ASan +
# UBSan and run them there, then the fuzz harnesses.
set -euo pipefail
cd "$(dirname "$0")/.."
toolchain/install-deps.sh
jobs=$(nproc)

cmake --preset default >/dev/null
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs"

cmake --preset debug >/dev/null
cmake --build --preset debug -j "$jobs"
# Every label under the sanitizers; the corpus label reads the Release
# corpus (PITVOL_CORPUS_DIR) instead of generating it again, and checks
# every 6th scan (tests/corpus/CMakeLists.txt).
ctest --preset debug -j "$jobs" -L 'unit|usb|corpus|cli' -E '^corpus_generate$' --fixture-exclude-setup pv_corpus

# libFuzzer harnesses (fuzz/, clang-14 + ASan + UBSan): a fixed number of
# executions each from the committed seeds (label fuzz; docs/reliability.md).
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$jobs"
ctest --preset fuzz -j "$jobs"
