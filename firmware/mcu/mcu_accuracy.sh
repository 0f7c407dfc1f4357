#!/usr/bin/env bash
# The MCU configuration against the default one and against the exact
# volume, over a simulated corpus: the tables of docs/targets.md.
#   firmware/mcu/mcu_accuracy.sh build/bin/pitvol-replay build/corpus
# (pitvol-sim corpus --out build/corpus; --set holdout, --set stress).
# Prints a markdown table (one row per scan of the manifest) and a summary:
# scans both configurations measure, how many within 0.3 % of the default,
# the median and worst |difference|, and on how many the MCU's interval
# holds the exact volume.
set -euo pipefail
replay=$1 corpus=$2
manifest="$corpus/manifest.csv"
[ -f "$manifest" ] || { echo "no $manifest" >&2; exit 1; }
# Columns of the manifest by name: case, exact_volume_cm3.
read -r col_case col_exact < <(head -1 "$manifest" | tr ',' '\n' |
  awk '$1 == "case" { c = NR } $1 == "exact_volume_cm3" { e = NR } END { print c, e }')
mapfile -t scans < <(tail -n +2 "$manifest" | cut -d, -f"$col_case" | sort)
plys=()
for s in "${scans[@]}"; do plys+=("$corpus/$s.ply"); done
# "# status NAME volume_cm3 V depth_mm D layers L interval_cm3 I" per scan.
summary() { awk '$1 == "scan" { s = $2; sub(/\.ply$/, "", s) }
                 $1 == "#" && $2 == "status" { print s, $3, $5, $11 }'; }
join <("$replay" "${plys[@]}" | summary | sort) \
     <("$replay" --mcu-config "${plys[@]}" | summary | sort) |
  join - <(tail -n +2 "$manifest" | cut -d, -f"$col_case,$col_exact" | tr ',' ' ' | sort) |
  awk '
    function abs(x) { return x < 0 ? -x : x }
    BEGIN { print "| scan | default config, cm3 | MCU config, cm3 | MCU vs default | MCU vs exact | MCU interval | interval holds exact |"
            print "|---|---|---|---|---|---|---|" }
    # name dstatus dvol div mstatus mvol miv exact
    { if ($5 != "PV_OK" || $2 != "PV_OK") {
        printf "| %s | %s | %s |  |  |  |  |\n", $1, ($2 == "PV_OK" ? sprintf("%.1f", $3) : $2), $5
        next }
      d = 100 * ($6 - $3) / $3; e = 100 * ($6 - $8) / $8; holds = abs($6 - $8) <= $7
      printf "| %s | %.1f | %.1f | %+.2f %% | %+.2f %% | +-%.2f %% | %s |\n", $1, $3, $6, d, e, 100 * $7 / $6, holds ? "yes" : "**no**"
      n++; diff[n] = abs(d); within += abs(d) <= 0.3; held += holds }
    END {
      for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (diff[j] < diff[i]) { t = diff[i]; diff[i] = diff[j]; diff[j] = t }
      med = n % 2 ? diff[(n + 1) / 2] : (diff[n / 2] + diff[n / 2 + 1]) / 2
      printf "\nboth measure %d of %d; within 0.3 %% of the default: %d; median |difference| %.2f %%, worst %.2f %%; interval holds the exact volume: %d of %d\n", n, NR, within, med, diff[n], held, n }'
