#!/usr/bin/env bash
# cppcheck over the code that runs on the targets: core, drivers and the
# MCU app (warnings and portability; CI fails on any finding).
# Two findings in the lead's files are suppressed by name, with the reason:
#  - memsetClassFloat: zeroing a result struct with doubles is all-zero
#    bits = 0.0 on every IEEE-754 target we build for;
#  - legacyUninitvar in session.cpp: a placement new into the caller's
#    block, which cppcheck 2.10 reads as an uninitialised pointer;
#  - invalidPointerCast in surface_model.cpp and angle_bins.cpp:
#    integer scratch kept in unused double/float arrays of the workspace;
#    no value is read back as the other type.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v cppcheck >/dev/null || { echo "cppcheck missing: toolchain/install-deps.sh --cross" >&2; exit 1; }
cppcheck --quiet --enable=warning,portability --std=c++17 --language=c++ \
  --error-exitcode=1 --inline-suppr \
  --suppress=memsetClassFloat:core/session/measure.cpp \
  --suppress=legacyUninitvar:core/session/session.cpp \
  --suppress=invalidPointerCast:core/surface/surface_model.cpp \
  --suppress=invalidPointerCast:core/surface/angle_bins.cpp \
  -I core -I core/include -I drivers/usb/include \
  core drivers firmware/mcu
echo "cppcheck: clean"
