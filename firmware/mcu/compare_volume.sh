#!/usr/bin/env bash
# The MCU configuration against the default one: every scan must end with
# the same status, and a measured volume within MAX_PCT of the default's.
# TARGET_OUTPUT is the Cortex-M7's pv-replay output (written by the
# mcu_bits_mcu_config test, which also proves it equal to the host's bits);
# REFERENCE CMD is the host's pv-replay with the default configuration,
# standing for the board (bits_board_default proves them equal).
# Usage: compare_volume.sh MAX_PCT TARGET_OUTPUT "REFERENCE CMD" SCAN...
set -euo pipefail
max_pct=$1 target_out=$2 ref_cmd=$3
shift 3
[ -s "$target_out" ] || { echo "FAIL: no target output $target_out (run mcu_bits_mcu_config first)" >&2; exit 1; }
ref_out="$(dirname "$target_out")/reference_default.txt"
# shellcheck disable=SC2086
$ref_cmd "$@" > "$ref_out"
# "scan NAME" then "# status STATUS volume_cm3 V ...": NAME STATUS V per scan.
summary() { tr -d '\r' < "$1" | awk '$1 == "scan" { s = $2 } $1 == "#" && $2 == "status" { print s, $3, $5 }'; }
join <(summary "$ref_out" | sort) <(summary "$target_out" | sort) |
  awk -v max="$max_pct" -v want=$# '
    { n++; d = ($3 != 0) ? 100 * ($5 - $3) / $3 : 0
      ok = ($2 == $4) && ($2 != "PV_OK" || (d <= max && d >= -max))
      printf "%-24s default %-22s %12.3f  mcu %-22s %12.3f  %+7.3f %%  %s\n", $1, $2, $3, $4, $5, d, ok ? "ok" : "FAIL"
      if (!ok) bad++ }
    END { if (n != want) { print "FAIL: " n " of " want " scans in both outputs"; exit 1 }
          if (bad) { print "FAIL: " bad " scans differ by more than " max " % (or in status)"; exit 1 }
          print "all " n " scans within " max " %" }'
