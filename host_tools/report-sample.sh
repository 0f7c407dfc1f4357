#!/usr/bin/env bash
# The scan report of the sample scan: install what is missing, build
# (Release, build/), measure build/samples/sample_pit.ply and write the page
# build/report/sample_report.html (docs/report.md). Extra arguments go to
# pitvol-report (e.g. --pdf build/report/sample_report.pdf, --mass-g 23500).
set -euo pipefail
cd "$(dirname "$0")/.."
toolchain/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default --target pitvol sample_scan
mkdir -p build/report
echo
echo "build/bin/pitvol-report build/samples/sample_pit.ply --out build/report/sample_report.html $*"
exec build/bin/pitvol-report build/samples/sample_pit.ply --out build/report/sample_report.html "$@"
