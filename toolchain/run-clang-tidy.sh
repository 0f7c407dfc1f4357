#!/usr/bin/env bash
# clang-tidy over the code that runs on the targets: core and drivers,
# with the compile commands of the default preset (build/). Any finding
# fails. Not part of tests/run-tests.sh: it costs about 2.3 min of CPU
# (70 s on an idle 2-core machine; Eigen's headers, parsed per file, are
# most of it), over the 1 min CI budget it was given. Run it before
# committing changes to core/ or drivers/ (docs/targets.md).
#
# Checks: bugprone-* and performance-*, except
#  - bugprone-easily-swappable-parameters: style (35 hits, no bugs);
#  - bugprone-implicit-widening-of-multiplication-result: index products
#    of validated capacities (pv_config_validate caps point slots at 2^26),
#    and on the Cortex-M7 size_t is 32 bits, so widening would protect
#    nothing; -Wconversion already rejects narrowing;
#  - performance-no-int-to-ptr: aligning a pointer into the caller's block
#    (core/thinning) is the point of the code.
# Feature-test macros (_GNU_SOURCE, _DEFAULT_SOURCE) are allowed reserved
# identifiers. Single findings judged intentional carry a NOLINT with the
# reason on the line.
#   toolchain/run-clang-tidy.sh [FILE...]   (default: every .c/.cpp in core/ and drivers/)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v run-clang-tidy >/dev/null || { echo "clang-tidy missing: toolchain/install-deps.sh --cross" >&2; exit 1; }
[ -f build/compile_commands.json ] || cmake --preset default >/dev/null
checks='-*,bugprone-*,performance-*,-bugprone-easily-swappable-parameters,-bugprone-implicit-widening-of-multiplication-result,-performance-no-int-to-ptr'
config="{Checks: '$checks', WarningsAsErrors: '*', CheckOptions: [{key: bugprone-reserved-identifier.AllowedIdentifiers, value: '_GNU_SOURCE;_DEFAULT_SOURCE'}]}"
if [ $# -gt 0 ]; then files=("$@"); else mapfile -t files < <(find core drivers \( -name '*.c' -o -name '*.cpp' \) | sort); fi
# run-clang-tidy takes regexes matched against the compile database's paths.
# -Wno-unknown-warning-option: GCC-only flags of the build (maybe-uninitialized).
run-clang-tidy -p build -j "$(nproc)" -quiet -config="$config" -extra-arg=-Wno-unknown-warning-option \
  -header-filter="$PWD/(core|drivers)/.*" "${files[@]/#/$PWD/}" > build/clang-tidy.log 2>&1 || true
if grep -q 'warning:\|error:' build/clang-tidy.log; then
  grep -A3 'warning:\|error:' build/clang-tidy.log | sed 's/\x1b\[[0-9;]*m//g' >&2
  echo "clang-tidy: findings above (build/clang-tidy.log)" >&2
  exit 1
fi
echo "clang-tidy: clean (${#files[@]} files)"
