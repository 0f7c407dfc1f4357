#!/usr/bin/env bash
# Every test: install what is missing, then
#  1. Release (build/): every CTest label registered by default (unit,
#     corpus, usb, cli, serial, e2e, report: about 30 s, docs/report.md;
#     package: the amd64 .deb unpacked and run);
#  2. Debug with ASan + UBSan (build-debug/): unit, usb, cli, serial, e2e
#     and a sixth of the corpus, under the sanitizers (label slow stays in
#     Release);
#  3. the libFuzzer harnesses, a fixed number of executions each (fuzz);
#  4. the board (aarch64, from a sysroot of Debian's arm64 packages; unit,
#     bits, e2e and package tests under qemu-aarch64) and MCU (Cortex-M7, under
#     qemu-system-arm) builds, their tests and the same-bits comparison
#     with the Release build (docs/targets.md);
#  5. cppcheck and the size report.
# Labels CI skips (docs/reliability.md, docs/accuracy.md): peers, soak,
# holdout, stress, envelope, slow under the sanitizers, long fuzzing.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's start, as wall clock since the start (CI must stay within 20
# minutes on a 2-core machine: docs/targets.md "CI time").
stage() { echo "pitvol: [$((SECONDS / 60)) min $((SECONDS % 60)) s] $*" >&2; }
stage "dependencies"
toolchain/install-deps.sh --cross --browser  # --browser: the report label
jobs=$(nproc)
# Every dependency is required: one that is missing stops the configure and
# names its Debian package, instead of leaving a part and its tests out.
require=-DPITVOL_REQUIRE_ALL=ON

stage "default: build, tests"
cmake --preset default "$require" >/dev/null
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs" -LE 'peers|soak|envelope'  # peers: minutes a scan; soak: 200 scans; envelope: 300 (by hand)

stage "debug (ASan + UBSan): build, tests"
cmake --preset debug "$require" >/dev/null
cmake --build --preset debug -j "$jobs"
# The corpus label reads the Release corpus (PITVOL_CORPUS_DIR) instead of
# generating it again, and checks every 6th scan (tests/corpus/CMakeLists.txt).
# sim_same_bits runs in Release only: ASan under qemu-x86_64 (its emulated
# CPUs) is killed.
ctest --preset debug -j "$jobs" -L 'unit|usb|corpus|cli|serial|e2e' -LE slow \
  -E '^(corpus_generate|sim_same_bits)$' --fixture-exclude-setup pv_corpus

# libFuzzer harnesses (fuzz/, clang-14 + ASan + UBSan): a fixed number of
# executions each from the committed seeds (label fuzz; docs/reliability.md).
stage "fuzz: build, tests"
cmake --preset fuzz "$require" >/dev/null
cmake --build --preset fuzz -j "$jobs"
ctest --preset fuzz -j "$jobs"

# Board and MCU: after the Release tests, which generate the corpus scans
# the bits tests replay.
stage "board (aarch64): sysroot, build, tests"
cmake --preset board "$require" >/dev/null
cmake --build --preset board -j "$jobs"
ctest --preset board -j "$jobs" -L 'unit|bits|e2e|package' -LE slow
stage "mcu (Cortex-M7): build, tests"
cmake --preset mcu "$require" >/dev/null
cmake --build --preset mcu -j "$jobs"
ctest --preset mcu -j "$jobs" -L mcu
stage "cppcheck, size report"
toolchain/run-cppcheck.sh
toolchain/size-report.sh   # docs/memory.md: refresh with --write
stage "all passed"
