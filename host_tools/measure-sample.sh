#!/usr/bin/env bash
# The main job: install what is missing, build (Release, build/), generate
# the deterministic sample scan and measure it with the pitvol CLI.
# Extra arguments go to `pitvol measure` (e.g. --json).
set -euo pipefail
cd "$(dirname "$0")/.."
toolchain/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default
echo
echo "build/bin/pitvol measure build/samples/sample_pit.ply $*"
exec build/bin/pitvol measure build/samples/sample_pit.ply "$@"
