#!/usr/bin/env bash
# pitvol-sim sweep through its command line, at a twentieth of the points:
# one case made again alone (--index, another process) is the same bytes as
# in the whole sweep, the manifest describes every file written (point
# counts, twins, units in the PLY header), and pitvol-accuracy --envelope
# reads it. The scans' truth and conditions: test_envelope.
# Usage: sweep_cli.sh PITVOL_SIM PITVOL_ACCURACY WORK_DIR
set -euo pipefail
sim=$1 acc=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
"$sim" sweep --seed 1 --count 12 --thin 0.05 --out "$work/a" 2>/dev/null
for i in 3 5; do  # cm units; a long scan and its twin
  "$sim" sweep --seed 1 --index $i --thin 0.05 --out "$work/one-$i" 2>/dev/null
  for f in "$work/one-$i"/*.ply; do
    cmp -s "$f" "$work/a/${f##*/}" || fail "--index $i wrote ${f##*/} unlike the whole sweep"
  done
  tail -n +2 "$work/one-$i/manifest.csv" | while read -r line; do
    grep -qxF "$line" "$work/a/manifest.csv" || fail "--index $i: manifest line differs: $line"
  done
done
# Every manifest row: its file, its point count in the PLY header and size.
col() { head -1 "$work/a/manifest.csv" | tr ',' '\n' | grep -nx "$1" | cut -d: -f1; }
c_case=$(col case) c_points=$(col points) c_set=$(col set) c_units=$(col units) c_twin=$(col twin)
rows=0 twins=0
while IFS=, read -r -a f; do
  name=${f[$((c_case - 1))]} points=${f[$((c_points - 1))]} units=${f[$((c_units - 1))]}
  ply="$work/a/$name.ply"
  [ -f "$ply" ] || fail "$name.ply missing"
  n=$(grep -a -m1 '^element vertex' "$ply" | awk '{print $3}')
  [ "$n" = "$points" ] || fail "$name: header says $n points, manifest $points"
  head_bytes=$(grep -a -b -m1 '^end_header' "$ply" | cut -d: -f1)
  [ $(( $(stat -c %s "$ply") - head_bytes - 11 )) -eq $(( 12 * n )) ] || fail "$name: size is not the header's count"
  grep -a -q "^comment units $units " "$ply" || fail "$name: header does not say units $units"
  twin=${f[$((c_twin - 1))]}
  if [ -n "$twin" ]; then
    grep -q "^$twin," "$work/a/manifest.csv" || fail "$name: twin $twin not in the manifest"
  fi
  if [ "${f[$((c_set - 1))]}" = sweep ]; then rows=$((rows + 1)); else twins=$((twins + 1)); fi
done < <(tail -n +2 "$work/a/manifest.csv")
[ $rows -eq 12 ] || fail "$rows scans in the manifest, not 12"
grep -q '"measure_units": null' "$work/a/manifest.json" || fail "manifest.json lacks measure_units"
grep -q '"world_from_pit": {"R": \[' "$work/a/manifest.json" || fail "manifest.json lacks the pose"
echo "sweep: 12 scans and $twins twins; --index 3 and 5 the same bytes"
# --slabs: a sweep case's pit as drawn (its scale and shape), not the
# family's nominal pit: against empty layers from under the floor to over
# the rim, the slabs' true void sums to the manifest's exact volume (case 2,
# a 0.4 m3 pit drawn 4x its family's nominal size).
c_exact=$(col exact_volume_cm3) c_depth=$(col depth_mm)
row=$(grep '^s1-002-' "$work/a/manifest.csv" | head -1)
exact=$(cut -d, -f"$c_exact" <<<"$row") depth=$(cut -d, -f"$c_depth" <<<"$row")
awk -v d="$depth" 'BEGIN { print "z_mm,area_mm2"; for (z = -9.75; z < d + 10; z += 0.5) printf "%.2f,0\n", z }' \
  > "$work/empty-layers.csv"
truth=$("$sim" sweep --seed 1 --index 2 --slabs "$work/empty-layers.csv" --step 1000 | awk -F, '$1 == "all" { print $3 }')
awk -v a="$truth" -v b="$exact" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(b > 0 && d <= 0.001 + 1e-6 * b) }' ||
  fail "sweep --slabs: the true void of case 2 sums to $truth cm3, its exact volume is $exact"
echo "sweep --slabs: case 2's pit as drawn ($truth cm3)"
"$acc" "$work/a" --envelope --markdown > "$work/table.md"
grep -q '^| mean abs error <= 0.05 %' "$work/table.md" || fail "no targets in the envelope table"
grep -q '^### The envelope: family x size x condition' "$work/table.md" || fail "no envelope table"
echo "pitvol-accuracy --envelope: table written"
