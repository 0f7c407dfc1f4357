#!/usr/bin/env bash
# The MCU configuration on the host against the default configuration:
# compare_volume.sh with the host's `pitvol-replay --mcu-config` standing
# for the M7 (mcu_bits_mcu_config proves their bits equal), for scans the
# M7 test does not carry and hosts without qemu-system-arm.
# Usage: host_vs_default.sh MAX_PCT REPLAY OUT_DIR SCAN...
set -euo pipefail
max_pct=$1 replay=$2 out_dir=$3
shift 3
mkdir -p "$out_dir"
"$replay" --mcu-config "$@" > "$out_dir/target.txt"
exec "$(dirname "$0")/compare_volume.sh" "$max_pct" "$out_dir/target.txt" "$replay" "$@"
