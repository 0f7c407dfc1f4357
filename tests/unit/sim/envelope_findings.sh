#!/usr/bin/env bash
# Findings of the envelope sweeps (tuning seed 1, and 1300 once looked at),
# each made again by pitvol-sim and measured by pitvol: what each must read, and in the
# comments what a pitvol without the guard reads. The scans are the sweep's
# own, at full density.
# Usage: envelope_findings.sh PITVOL_SIM PITVOL WORK_DIR
set -euo pipefail
sim=$1 pitvol=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
# measure INDEX [SEED]: sets status, check, volume and exact for the sweep
# case (seed 1 unless given); with measure_config=FILE, measured with that
# configuration; with sweep_args (--family F --condition C), from that
# sweep; with twin=1, the case's 1x twin. The sweep writes the case and
# its twin together; with keep=1 they stay for the next measure.
measure() {
  local dir="$work/$1-${2:-1}"
  # shellcheck disable=SC2086
  [ -f "$dir/manifest.csv" ] ||
    "$sim" sweep --seed "${2:-1}" --index "$1" ${sweep_args:-} --out "$dir" 2>/dev/null
  local ply
  if [ -n "${twin:-}" ]; then
    ply=$(ls "$dir"/*-1x.ply | head -1)
  else
    ply=$(ls "$dir"/*.ply | grep -v -- '-1x.ply' | head -1)
  fi
  json=$("$pitvol" measure "$ply" --json ${measure_config:+--config "$measure_config"} 2>/dev/null || true)
  status=$(grep -o '"status": "[A-Z_]*"' <<<"$json" | cut -d'"' -f4)
  check=$(grep -o '"failed_check": "[A-Z_]*"' <<<"$json" | cut -d'"' -f4 || true)
  volume=$(grep -o '"volume_cm3": [0-9.e+-]*' <<<"$json" | cut -d' ' -f2)
  interval=$(grep -o '"interval_cm3": [0-9.e+-]*' <<<"$json" | cut -d' ' -f2)
  exact=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "exact_volume_cm3") c = i }
                   NR == 2 { print $c }' "$dir/manifest.csv")
  [ -n "${keep:-}" ] || rm -rf "$dir"
}
inside() {  # the truth inside the reported interval
  awk -v v="$volume" -v e="$exact" -v i="$interval" 'BEGIN { d = v - e; if (d < 0) d = -d; exit !(d <= i) }'
}
# twin_within INDEX SEED PERCENT: the case (v_case) against its 1x twin
# (v_twin), one sweep for both; status, volume, interval and exact are the
# case's after it.
twin_within() {
  keep=1 measure "$1" "$2"
  local s=$status c=$check v=$volume i=$interval e=$exact
  twin=1 measure "$1" "$2"
  v_twin=$volume
  status=$s check=$c volume=$v interval=$i exact=$e v_case=$v
  awk -v a="$v_case" -v b="$v_twin" -v p="$3" 'BEGIN { d = (a - b) / b * 100; if (d < 0) d = -d; exit !(d <= p) }'
}
measured_inside() {  # measured_inside LABEL: PV_OK, the truth inside the interval
  [ "$status" = PV_OK ] && inside || fail "$1: $status $check $volume +/- $interval cm3 against $exact"
}
refused_by() {  # refused_by CHECK LABEL: PV_ERR_NOT_A_PIT, refused by PV_PIT_CHECK_<CHECK>
  [ "$status" = PV_ERR_NOT_A_PIT ] && [ "$check" = "PV_PIT_CHECK_$1" ] ||
    fail "$2: $status $check $volume +/- $interval cm3 against $exact"
}
within() {  # within PERCENT: the volume's error against exact
  awk -v v="$volume" -v e="$exact" -v p="$1" 'BEGIN { d = (v - e) / e * 100; if (d < 0) d = -d; exit !(d <= p) }'
}
# A second pass 17 mm higher: a doubled floor (without the check: +10.4 %
# with PV_OK).
measure 206
refused_by DOUBLED_FLOOR "206 (vertical slip)"
# A 0.4 m3 pit 804 mm deep with a narrow ground ring: within range (960 mm),
# and measured although strays fill the rim-plane sectors (undug: -10 %).
measure 23
[ "$status" = PV_OK ] && within 0.1 || fail "23 (0.4 m3, 804 mm deep): $status $volume cm3 against $exact"
# 1.48 m across: wider than the grids' 320 mm radius, measured on grids
# scaled to it.
measure 46
[ "$status" = PV_OK ] && within 1.0 || fail "46 (741 mm radius): $status $volume cm3 against $exact"
# Its scan thins out 150 mm below the rim: no rim (taking the fading wall's
# top as the rim reads -19 % with PV_OK).
measure 267
[ "$status" = PV_ERR_NO_RIM ] || fail "267 (wall fading out): $status $volume cm3 against $exact"
# Fresh seed 1300 (looked at for the container lip): a pit without surround
# whose second pass slipped sideways. Both passes' wall tops make a ring at
# the rim with the outer copy's wall under its edge, as a container's lip
# and outer wall do, but nothing between them: a lip capped it and it read
# 153,083 +/- 1,618 cm3 for 155,808 with PV_OK.
measure 71 1300
[ "$status" = PV_ERR_NOT_A_PIT ] || fail "1300/71 (sideways slip, no surround): $status $volume cm3 against $exact"
# The opening found where the floor-plane frame does not show it (a
# support plane, else the scanner-upright frame; rim/support_plane.h):
# nominal pits with a ground ring were refused PV_ERR_NO_RIM: a bulge whose
# ground holds a quarter of the top band less a point (tuning seed 1300),
measure 128 1300
[ "$status" = PV_OK ] && within 0.1 || fail "1300/128 (ground under a quarter of the band): $status $volume cm3 against $exact"
# and a bowl whose floor fit was 9 deg off a 19 deg scan;
measure 145 1300
[ "$status" = PV_OK ] && within 0.25 || fail "1300/145 (bowl, floor fit 9 deg off): $status $volume cm3 against $exact"
# a rounded bowl in a container read +57 % with PV_OK: its floor fit was
# 37 deg off a 3.5 deg scan (tuning seed 1300).
measure 136 1300
[ "$status" = PV_OK ] && within 0.25 || fail "1300/136 (rounded bowl, container): $status $volume cm3 against $exact"
# A container whose lip the scan saw from far (6-23 top band points in a
# 2 deg bin): bins capped from their own few points counted the outer wall
# under the lip as pit, +4.4 % with PV_OK.
measure 222
[ "$status" = PV_OK ] && within 0.3 || fail "222 (container lip seen from far): $status $volume cm3 against $exact"
# A shorter second pass 23 mm higher: its floor is 5 % of the floor's
# points, under the 10 % the first slip rule asks for, but at one height
# and over a fifth of the floor (+14.7 % with PV_OK without the rule).
measure 113
refused_by DOUBLED_FLOOR "113 (short vertical slip)"
# Seed 1302 (looked at after its envelope table): a rounded bowl with a
# ground ring, scanned 44 deg off. Its floor fit is 36 deg off the ground,
# too steep for the ground there; the support plane found within 30 deg of
# it was a wall's tangent (28 deg): +81 % +/- 27 % with PV_OK. From the
# support plane's frame the ground is found.
measure 182 1302
[ "$status" = PV_OK ] && within 0.3 || fail "1302/182 (rounded bowl, 44 deg): $status $volume cm3 against $exact"
# A 1.2 L pit without surround whose protrusion's flat top, 22 mm below
# the rim, was taken for the ground: levelled on it, the rim at its height,
# -23.8 % with PV_OK (seed 1302, looked at after its table). A face with
# the scan spread over the heights above it is a ledge, not a ground; it
# must be refused or hold the truth in its interval.
measure 79 1302
[ "$status" != PV_OK ] || inside || fail "1302/79 (protrusion's top as ground): $status $volume +/- $interval cm3 against $exact"
# A textured pit whose ground (3 % of the points) the levelling found but
# whose 1 mm peak holds under a quarter of the top band: the rim fell to
# the wall's top, read on strays 19 mm above the ground, +6.1 % with PV_OK
# (seed 1302). The ground's plane is the rim there.
measure 276 1302
[ "$status" = PV_OK ] && within 0.3 || fail "1302/276 (ground under strays): $status $volume cm3 against $exact"
# A sparse 250 L rounded bowl without surround: no opening found from
# either start, the floor plane's frame (a tangent 9 deg off) and the
# wall's top read +28.5 % with PV_OK (seed 1302). No opening, no lid:
# refused NO_RIM, or levelled on an opening the turned starts agree on
# and inside its interval (-0.21 % +/- 0.64 %).
measure 69 1302
[ "$status" = PV_ERR_NO_RIM ] || { [ "$status" = PV_OK ] && inside; } ||
  fail "1302/69 (no opening found): $status $volume +/- $interval cm3 against $exact"
# A shallow wide pit whose ground ring holds under a quarter of the top
# band (20 % of the depth down the wall): levelled on its support plane,
# +0.27 %; the ground found in the narrow band reads -0.05 % (tuning seed 1).
measure 245
[ "$status" = PV_OK ] && within 0.2 || fail "245 (ground in the narrow band): $status $volume cm3 against $exact"
# An elliptical pit (tuning seed 1300): its wall crosses a 2 deg bin over
# several mm of radius, the points at the bin's inner end fell behind the
# band and counted as a second copy: refused DOUBLED_WALL.
measure 35 1300
[ "$status" = PV_OK ] && within 0.3 || fail "1300/35 (elliptical wall): $status $check $volume cm3 against $exact"
# A sparse scan of an elliptical pit (8-15 points per 2 deg bin, tuning
# seed 1): a neighbour under 8 points on one side or the other left most
# bins' bands unwidened along the angle, and the wall's inner points read
# as a second wall, refused DOUBLED_WALL at 0.30 (+0.13 % when measured).
# The slope comes from the nearest bins with 8 points, up to 3 bins away.
measure 109
[ "$status" = PV_OK ] && within 0.3 || fail "109 (sparse elliptical wall): $status $check $volume cm3 against $exact"
# A pit without surround with protrusions (seed 1302): a block's top
# 15 mm under the rim stood 48 times over the rim's level outside the
# wall, which a pit without surround leaves in one sector: refused
# DOUBLED_RIM. The check asks for a surround.
measure 63 1302
[ "$status" = PV_OK ] && within 0.3 || fail "1302/63 (no surround, protrusion's top): $status $check $volume cm3 against $exact"
# A rounded bowl (tuning seed 1300, ground ring, walked over 178 deg) has
# no level floor: the steep cells of its bottom put their own surface in
# the floor's ghost window, 3.15 % of the floor's points, and it was
# refused DOUBLED_FLOOR (limit 3 %). Counted over the level cells only
# (0.26 %): -0.87 % +/- 1.56 %.
measure 130 1300
measured_inside "1300/130 (rounded bowl's sloping bottom)"
# A cylinder in a container scanned over a 200 deg arc, 16 deg off: its
# floor fit 105 deg off, the rim plane found near that frame faced
# sideways, and a section through the wall, taken for the rim, was 0.18 of
# the widest: refused NARROW_MOUTH. Levelled from the scanner's axis
# instead: +0.34 %.
measure 67 1300
[ "$status" = PV_OK ] && within 0.5 || fail "1300/67 (opening found sideways): $status $check $volume cm3 against $exact"
# Openings found where fewer sectors show the wall's top, or far from the
# floor plane's frame (seeds 1301 and 1302, looked at for the no-opening
# refusals), each refused PV_ERR_NO_RIM before: a 782 mm deep pit without
# surround scanned 15 deg off, the top of its near wall unseen, its rim at
# one height in 22 of 36 sectors;
measure 20 1301
measured_inside "1301/20 (rim seen in 22 sectors)"
# rounded bowls scanned 49-58 deg off, their floor fits 33-49 deg off the
# rim plane: one with a ground ring (found again from the rim plane's
# frame), one without surround.
measure 107 1301
measured_inside "1301/107 (rounded bowl, 58 deg)"
measure 164 1302
measured_inside "1302/164 (rounded bowl, no surround, tilted)"
# A shallow wide pit whose floor fit lay 4 deg off: turned onto its
# ground ring, the whole scan above z = 0, the floor 20 mm up; the floor
# map found no cells at the bottom plane and the floor counted as points
# inside the void (tuning seed 5, sparse; refused POINTS_INSIDE at 0.72).
measure 0 5
measured_inside "5/0 (floor 20 mm above z = 0)"
# A 1.3 L necking pit whose undercut was unseen all round (31 % of the
# volume over unseen wall): refused WALL_GAP by default; with the limit
# loosened, bridged up the height gap it read -7.25 % +/- 0.99 % (tuning
# seed 5). Past the calibrated share the interval takes in the unseen
# volume.
measure 289 5
[ "$status" = PV_ERR_WALL_GAP ] || fail "5/289 (undercut unseen all round): $status $volume cm3 against $exact"
printf 'max_unseen_share = 1\n' > "$work/loose.conf"
measure_config=$work/loose.conf measure 289 5
measured_inside "5/289 loosened"
# A 0.38 m3 bulge without surround scanned 15 deg off: its rim seen in 16
# sectors, the other 20 showing lower wall: refused NO_RIM with the partial
# plane at 18 sectors; the highest edge, nowhere exceeded, is the rim.
measure 47 5
measured_inside "5/47 (rim in 16 sectors)"
# Vessels whose lip the scan saw from far in most bins (flat in 53 and 41
# bins of 180): the rest of the round had no cap, and where the path went
# outside, the bins read the outer wall under the lip. A tapered vessel
# (the inner wall runs in below, the outer stands plumb) read +1.64 %
# outside its interval, a rounded bowl +0.99 % (tuning seeds 11 and 12).
sweep_args="--family tapered --condition nominal" measure 49 11
[ "$status" = PV_OK ] && within 0.25 && inside || fail "11/49 (tapered vessel, lip seen from far): $status $volume +/- $interval cm3 against $exact"
sweep_args="--condition nominal" measure 72 12
[ "$status" = PV_OK ] && within 0.3 && inside || fail "12/72 (rounded bowl vessel, lip seen from far): $status $volume +/- $interval cm3 against $exact"
# And a textured pit without surround whose second pass slipped sideways:
# its two wall tops side by side look flat in 20 bins, 0.4-20 mm wide (a
# slip's width follows the angle, a vessel's wall is as thick all round).
# Capped as a vessel's round it read -8.8 % with PV_OK (tuning seed 5).
measure 27 5
[ "$status" = PV_ERR_NOT_A_PIT ] || fail "5/27 (sideways slip, textured, no surround): $status $volume cm3 against $exact"
# A 1.4 L pit whose second pass slipped 18 mm sideways, further than the
# doubled-wall window: each pass's ground over the other's mouth; +21.4 %
# with PV_OK (tuning seed 14).
sweep_args="--condition slip_lateral" measure 12 14
refused_by OVER_MOUTH "14/12 (sideways slip 18 mm, 1.4 L)"
# A 0.75 L elliptical pit slipped 19.9 mm sideways, 19 of its 242 points at
# the rim's height over the mouth (0.079): under the least count of 20 the
# check did not apply, +29.8 % with PV_OK (fresh seed 1341, looked at).
sweep_args="--family elliptical --condition slip_lateral" measure 339 1341
refused_by OVER_MOUTH "1341/339 (sideways slip 19.9 mm, 0.75 L)"
# A 1.6 L bulge without surround scanned 25 deg off, its frame at the
# warm-up upside down: the wall's top went to the floor store, the rim
# plane was fit 22 mm under the rim, -25.5 % with PV_OK (tuning seed 14,
# the 1x twin). Now the rim is found; the store's top is thin (refused).
twin=1 sweep_args="--condition slip_lateral" measure 22 14
[ "$status" != PV_OK ] || within 1.0 || fail "14/22 1x (frame upside down at warm-up): $status $volume cm3 against $exact"
# Passes slipped along the axis that the floor's second level shows, but
# the checks did not look: a deep narrow pit whose lower pass flooded a
# floor of 413 points (under the 500 the ghost share asks for; +1.14 %
# with PV_OK), and a 0.5 m3 pit without surround on grids scaled to its
# width (+3.12 % with PV_OK). Seed 1309 (drawn fresh, then looked at).
measure 41 1309
refused_by DOUBLED_FLOOR "1309/41 (slip down, small floor)"
measure 106 1309
refused_by DOUBLED_FLOOR "1309/106 (slip up, scaled grids)"
# A 0.15 m3 bowl-shaped container sent five times over: the floor store,
# nearly full after the first copy, took the second's first points (copies,
# and points the first copy had binned under another frame) before the
# repeat was seen, and halved: half of the floor kept, -0.65 % from the
# single copy. Now a full bin refuses a point it holds and the repeat mode
# starts there (fresh seed 1310, looked at for this).
twin_within 144 1310 0.05 ||
  fail "1310/144 (container sent five times over): $v_case cm3 against its single copy's $v_twin"
# A textured pit without surround whose second pass slipped 23 mm up: its
# floor lay in layers thinned as the wall's, the first pass's in the floor
# store, so point by point the second floor was 0.033 of the floor's
# points; +15.5 % with PV_OK. Weighed by the thinning: 0.46 (fresh seed
# 1310, looked at for this).
measure 259 1310
refused_by DOUBLED_FLOOR "1310/259 (slip up, thinned second floor)"
# A 1 L necking pit with stones, 27 % of its volume over the wall hidden
# under the neck: the bridge runs inside the bulge behind it, -4.8 % against
# +/- 2.5 % before the interval took in part of the unseen volume (tuning
# seed 8).
sweep_args="--family necking --condition stones" measure 38 8
measured_inside "8/38 (undercut 27 % unseen)"
# A bulge vessel scanned 28 passes: multipath over its thinned lip (layers
# less thinned than the lip's) made the rim plane's tops in half the
# sectors, the plane 0.6 mm high and tilted: +2.7 % from its single pass.
# Then +0.67 %: its lip flat in under half the bins, the round's widths
# spread by the outer wall's bulge, no vessel caps. Fresh seed 1309,
# looked at for this.
twin_within 282 1309 0.05 ||
  fail "1309/282 (vessel scanned 28 passes): $v_case cm3 against its single pass's $v_twin"
# A 129 L cylinder with a 0.79 L stone on its floor: the flood went round
# the stone, the floor was carried under it and the stone counted as void,
# +0.59 % against +/- 0.40 %. Now the stone's top bounds the void (fresh
# seed 1310, looked at for this).
measure 138 1310
measured_inside "1310/138 (stone on the floor)"
# A tapered pit 1 m across and 662 mm deep without ground: from 524k
# points on its last provisional frame lay on the wall, 81 deg off, and the far wall
# beyond that frame's top (1.3 % of the points since) refused it
# DEPTH_EXCEEDS_CAPACITY; a grid's top counts against the depth only where
# it caps the pit (fresh seed 1311, looked at for this).
measure 278 1311
measured_inside "1311/278 (provisional frame on the wall)"
# A necking container scanned once: a band all round under its neck
# unseen (24 % of the volume), the fill from above carrying the neck's
# radius down where the wall bulges back out: -8.3 % PV_OK against an
# interval of +/- 4.2 % (fresh seed 1312, the 1x twin of a slipped scan;
# looked at for this). The wall under an overhang reaches the seen wall
# below it in the interval.
sweep_args="--family necking --condition slip_lateral" twin=1 measure 165 1312
measured_inside "1312/165 1x (under a neck)"
# A 960 mm tapered vessel scanned at 25 deg: over 66 deg the scan saw
# neither its lip nor the inner wall's top, those bins took no cap, and
# read the outer wall up to 93 mm behind the inner wall: +1.31 % PV_OK
# against +/- 0.42 % (fresh seed 1312, looked at for this).
sweep_args="--family tapered --condition nominal" measure 128 1312
measured_inside "1312/128 (vessel's lip unseen over 66 deg)"
# A 0.06 m3 shallow pit with ground scanned 42 deg off: neither the floor
# fit nor the scanner's axis found its opening (NO_RIM); from the axis
# turned 30 and 50 deg the ground most starts agree on (tuning seed 1311,
# looked at for this).
sweep_args="--family shallow_wide --condition tilted" measure 37 1311
measured_inside "1311/037 (held 42 deg off)"
# A sparse rounded bowl with ground whose bottom 60 mm went unseen: the
# fill carried the lowest seen radius down to the bottom, +1.92 % against
# +/- 1.0 % (tuning seed 1311, looked at for this); the interval's low
# spread follows the seen wall's narrowing down.
sweep_args="--family rounded_bowl --condition sparse" measure 59 1311
measured_inside "1311/059 (bottom unseen)"
# A bowl 516 mm deep scanned ten times over: the stored points thin to one
# or two per floor cell, a few wall bins on the bottom's slope fall short
# of floor points and count as seen, and the floor bins filled from them
# cut the floor up the slope at their radius: -0.84 % PV_OK against its
# single scan's -0.10 % (fresh seed 1312, looked at for this). A floor bin
# reaches as far as the wall above it.
sweep_args="--family bowl --condition long" twin_within 211 1312 0.05 ||
  fail "1312/211 (bowl scanned 10x) against its 1x: $v_case against $v_twin cm3"
[ "$status" = PV_OK ] && within 0.2 && inside || fail "1312/211 (bowl scanned 10x): $status $volume +/- $interval cm3 against $exact"
# A rounded bowl in a container seen over part of its round: -1.47 % PV_OK
# against +/- 1.1 % (tuning seed 1312), for the same reason.
sweep_args="--family rounded_bowl --condition arc" measure 203 1312
[ "$status" = PV_OK ] && within 0.3 && inside || fail "1312/203 (rounded bowl, arc): $status $volume +/- $interval cm3 against $exact"
# The rim found below the top of the wall, the wall seen going on above it
# all round: a grooved rounded bowl without surround, its top band thinly
# seen over a dense groove ledge, the rim 16 mm low: -14.1 % PV_OK against
# +/- 1.0 % (fresh seed 1314, looked at for this); a 0.55 m3 cylinder
# scanned 59 deg off, its sparse ground unfound and the rim plane 29 mm
# under it: -3.8 % PV_OK against +/- 0.3 %. No rim, not a wrong volume.
# The bowl was levelled on its groove's ledge as a ground: refused there,
# it is levelled again without grounds (core/session/measure.cpp,
# ground_under_top), on its rim plane, and measures -1.0 % against
# +/- 1.25 %. The cylinder's frame is no ground: still refused.
sweep_args="--family rounded_bowl --condition grooves" measure 68 1314
measured_inside "1314/068 (rim under the wall's top, levelled again without grounds)"
sweep_args="--family cylinder --condition tilted" measure 64 1314
[ "$status" = PV_ERR_NO_RIM ] || fail "1314/064 (rim plane under the ground): $status $volume +/- $interval cm3 against $exact"
# Protrusion pits whose blocks' sides and tops put points behind the band
# over the whole ghost window, refused DOUBLED_WALL as a doubled wall
# (tuning seed 1311 #210 over an arc at 0.35; fresh seed 1314 #132, sparse,
# at 0.27, looked at for this): a second copy lies at one depth.
sweep_args="--family protrusions --condition arc" measure 210 1311
measured_inside "1311/210 (protrusions, arc)"
sweep_args="--family protrusions --condition sparse" measure 132 1314
measured_inside "1314/132 (protrusions, sparse)"
# A rounded bowl whose upright top meets the sloping bowl 31 mm under the
# rim: the bowl faces the scanner and holds more points per mm of height,
# so the top held 0.32 of the band below and was refused THIN_TOP as a
# slipped pass (tuning seed 1314, grooved). The ratio is taken for the
# bands' slopes.
sweep_args="--family rounded_bowl --condition grooves" measure 52 1314
measured_inside "1314/052 (rounded bowl, upright top)"
# A 1 m vessel (bowl, 7 mm lip) whose lip was seen flat in a fifth of the
# round: the caps carried round from those bins lay 1-2 mm inside the
# wall's top over 40 % of it, the wall's points there dropped, refused
# WALL_GAP (fresh seed 1315 #138's single scan, looked at for this). A cap
# lies at least at its bin's own inner edge.
twin=1 sweep_args="--family bowl --condition slip_vertical" measure 138 1315
measured_inside "1315/138 1x (1 m vessel, caps inside the wall)"
# A 1.5 m shallow pit with stones (757 mm of radius): the first model's
# widest wall bin read 787.6 mm from its clipped axis, past the 787.5 mm the
# margin leaves, refused TOO_WIDE (fresh seed 1316, looked at for this). The
# widest grids are tried, their model decides.
sweep_args="--family shallow_wide --condition stones" measure 183 1316
measured_inside "1316/183 (757 mm radius)"
# A second pass 8 mm higher in a 0.85 m wide vessel, measured on grids
# scaled to it, where the floor's ghost share did not run: +1.72 % with
# PV_OK outside +/- 0.47 % (tuning seed 1316). The share runs there too.
sweep_args="--family bulge --condition slip_vertical" measure 52 1316
refused_by DOUBLED_FLOOR "1316/052 (vertical slip, scaled grids)"
# A second pass 5.7 mm aside in a 162 mm wide elliptical pit: its wall
# bins hold about 5 points each, too few for the doubled wall's contrast,
# which then never ran: +4.35 % with PV_OK outside +/- 1.3 % (tuning seed
# 1313). Counted on 2 x 2 blocks of bins there.
sweep_args="--family elliptical --condition slip_lateral" measure 20 1313
refused_by DOUBLED_WALL "1313/020 (lateral slip, small pit)"
# A 143 mm vessel with a 4.1 mm lip scanned over an arc: the flat bins'
# lip under half the round, the grid's test for an outer wall (points 3 mm
# behind the band) missed its inner wall 4 mm behind, the outer wall went
# into the grid: refused DOUBLED_WALL at 0.46 (+1.26 % without the check;
# fresh seed 1317, looked at for this). The gap follows the lip's width.
sweep_args="--family cylinder --condition arc" measure 199 1317
measured_inside "1317/199 (vessel, 4.1 mm lip, arc)"
# A second pass 10.6 mm aside in a 146 mm wide textured pit without
# surround: past the doubled wall's 8 mm window, its two wall tops read as
# a vessel's lip, the model kept the inner of the two walls all round (the
# pits' intersection): -7.7 % with PV_OK outside +/- 0.8 % (tuning seed
# 1313). The other pass's wall behind it, as one shift puts it, refuses it.
sweep_args="--family textured --condition slip_lateral" measure 63 1313
refused_by SHIFTED_WALL "1313/063 (lateral slip past the window, read as a vessel)"
# Its single pass measures.
twin=1 sweep_args="--family textured --condition slip_lateral" measure 63 1313
measured_inside "1313/063 1x"
# A second pass 5.5 mm aside in a 0.35 m3 hand-dug pit 783 mm across,
# measured on grids scaled to it where the wall's contrast was not checked:
# +0.81 % with PV_OK outside +/- 0.36 % (tuning seed 1333). The contrast
# holds there at a higher limit (0.45; the slip reads 0.53); its single
# pass (0.004) measures.
keep=1 measure 324 1333
refused_by DOUBLED_WALL "1333/324 (lateral slip on scaled grids)"
twin=1 measure 324 1333
measured_inside "1333/324 1x"
# A 2.3 L protrusion pit scanned tilted: its blocks' edges hold two surfaces in
# a bin, and on its few dense bins (69 and 67 in the two pairs of sectors)
# where the blocks stood made 0.23 of thick-bin contrast: refused
# DOUBLED_WALL (tuning seed 1333). Less twice its standard error: 0.08.
measure 476 1333
measured_inside "1333/476 (protrusion pit, thick bins by chance)"
# A 1.0 L bulge with ground, a second pass 3.8 mm aside. Its wall holds
# one or two points a bin (about 0.3 a mm2: the ground and the floor hold
# the rest), too few for the wall's contrast even on pooled blocks: +2.99 %
# with PV_OK outside +/- 1.41 % (fresh seed 1334, then looked at). Counted
# over its 10 deg sectors, 16 of 36 hold the second wall behind the first;
# its single pass's, none.
keep=1 measure 866 1334
refused_by DOUBLED_SPARSE_WALL "1334/866 (lateral slip on a sparse 1 L wall)"
twin=1 measure 866 1334
measured_inside "1334/866 1x"
# A rounded bowl 87 L held 58 deg off: the floor-plane start settled 22
# deg off it and found an opening whose section was a sixth of the pit's
# below it, refused NARROW_MOUTH (tuning seed 1311). The frame from the
# scanner's axis, 94 deg from that one, measures it.
sweep_args="--family rounded_bowl --condition tilted" measure 59 1311
measured_inside "1311/059 (rounded bowl held 58 deg off)"
# A second pass 12 mm aside in a 785 mm deep pit without surround,
# refused POINTS_INSIDE; the scanner's axis gives the same frame (0.02 deg
# from it), from which it reads -1.5 % outside +/- 0.3 % with PV_OK
# (tuning seed 1314): the refusal was the pit's, not the frame's.
sweep_args="--family deep_narrow --condition slip_lateral" measure 21 1314
refused_by POINTS_INSIDE "1314/021 (lateral slip, same frame from the axis)"
# An elliptical pit without surround held 57 deg off: the floor-plane
# start read 141 deg, the scanner's axis found a plane 33 deg off, both
# refused NARROW_MOUTH; of the turned starts three agree on the rim plane
# (57.4-57.7 deg), the grounds they found elsewhere two at most, and taken
# before other planes they were refused too (tuning seed 1312). A retry
# takes the plane most starts agree on.
sweep_args="--family elliptical --condition tilted" measure 90 1312
measured_inside "1312/090 (pit without surround held 57 deg off)"
# A 1.2 L cylinder without surround scanned 25 passes: the rim plane
# through the sectors' third-highest points rose with their count, 0.17 mm
# over its single pass's, +0.21 % from it (the pass itself -0.004 %). The
# lid from the heights of the points about the plane (rim/rim_profile.h)
# reads both within 0.03 % of each other (seed 1323, looked at for this).
sweep_args="--family cylinder --condition long" twin_within 576 1323 0.05 ||
  fail "1323/576 (1 L pit without surround, 25 passes): $v_case cm3 against its single pass's $v_twin"
# A 1.1 m shallow pit without surround held 46 deg off: no opening from
# the floor plane or the scanner's axis; two turned starts found a
# "ground" along its side, taken first, the rim 1123 mm (its width) over
# the bottom: refused DEPTH_EXCEEDS_CAPACITY (seed 1324, looked at for
# this). Retried from the turned axis, the plane most starts agree on.
sweep_args="--family shallow_wide --condition tilted" measure 499 1324
measured_inside "1324/499 (shallow pit held 46 deg off, a ground along its side)"
# A 0.9 L bulging pit without surround, its single pass first levelled
# upside down: the wall's top 20 mm went to the floor store, the thin-top
# check counted the layer store alone and refused it at 0 (seed 1324,
# looked at for this). Counted in both stores, measured.
sweep_args="--family bulge --condition long" twin=1 measure 397 1324
measured_inside "1324/397 1x (wall's top in the floor store)"
# A 1.3 L hand-dug pit without surround, its single pass levelled upside
# down from the floor: from the turned axis the strict ground fit took
# the wall's top 2 mm (a ring 2.6 mm wide) for a ground 1.4 mm under the
# rim, -2.8 % outside its interval, refused only because the thin-top
# check missed the floor store's points (tuning seed 1314). After a turn
# a plane narrower than a ground ring (20 mm) with the wall going on above
# it is no ground: the rim plane stays.
sweep_args="--family hand_dug --condition slip_lateral" twin=1 measure 5 1314
measured_inside "1314/005 1x (wall's top taken for a ground after a turn)"
# A 3.4 L elliptical pit with grooves and a ground ring: a groove's shadow
# over its dense upper flank, then the wall again, read as a pass slipped
# 21 mm (the top 0.27 of the band below): refused THIN_TOP (tuning seed
# 1324). A slipped pass shows its own ground ring at the step's depth; this
# ring, seen in 30 of 36 sectors, has nothing under the rim.
sweep_args="--family elliptical --condition grooves" measure 482 1324
measured_inside "1324/482 (grooved, a ring and no second level)"
# And the vertical slip only the thin top refuses: a container's second
# pass 18 mm off, its lip seen in 13 sectors, the other pass's 14 points
# 19.5 mm under the rim (+2.15 % with PV_OK without the check; seed 1320).
sweep_args="--family hand_dug --condition slip_vertical" measure 145 1320
refused_by THIN_TOP "1320/145 (container slipped 18 mm up)"
# A 109 L textured pit with grooves: the grooves' upper flanks, hidden
# from a scanner looking down, bridged along the line of sight from the
# lower flank's bin to the wall above: -0.14 % (tuning seed 1324). A band
# of at most 6 mm under a narrower seen bin is an undercut, bridged at the
# lower bin's radius.
sweep_args="--family textured --condition grooves" measure 609 1324
[ "$status" = PV_OK ] && within 0.05 || fail "1324/609 (textured, grooves' upper flanks): $status $check $volume cm3 against $exact"
# A 249 L textured pit without surround (sent 5 times over; its single
# copy reads the same): its rough top looked flat in 37 bins, and behind
# the thin lip's 1 mm gap its grooves counted as a vessel's inner wall
# (0.20 of the points): capped as a vessel's, the wall beyond the caps was
# lost, -0.80 % against +/- 0.63 % (tuning seed 1324). The vessels left
# undecided read 0.22 and more.
sweep_args="--family textured --condition duplicates" measure 498 1324
measured_inside "1324/498 (textured top taken for a vessel's lip)"
# A 170 L protrusion pit without surround, its single pass: a 29 mm
# block's top 40 mm under the rim, the wall above it thinly seen (1.2 % of
# the sample), was taken for the ground, then refused NO_RIM with the wall
# above that rim in 32 of 36 sectors (tuning seed 1324). A flat face in 4
# sectors or fewer with the wall above it in 16 or more is a block's top.
sweep_args="--family protrusions --condition long" twin=1 measure 789 1324
measured_inside "1324/789 1x (a block's top taken for the ground)"
# A 1.2 L necking pit in a container: the neck's underside and the flank
# above it lie 10-35 mm over the floor's outer cells, 19 % of the floor's
# points in the slipped-floor window (and 11 % weighed): refused
# DOUBLED_FLOOR (tuning seed 1324). Points on the wall's surface there are
# wall, not a second floor.
sweep_args="--family necking --condition nominal" measure 42 1324
measured_inside "1324/42 (a neck over the floor)"
# A 0.86 L protrusion pit with ground scanned in 12 passes: its floor
# store thinned more than the layers over it, where multipath over the
# blocks' tops lies, so 5.1 % of the floor's points counted lay 8-40 mm above it
# (0.15 of the cells): refused DOUBLED_FLOOR as a shorter slipped pass
# (tuning seed 1324). Weighed by the thinning: 4.1 %, under the 6 % a
# slipped pass's floor shows.
sweep_args="--family protrusions --condition long" measure 265 1324
measured_inside "1324/265 (long scan, multipath over the floor)"
# A 220 L bulge with a ground ring seen narrower than the bulge reaches
# under the overhang: the ring's caps, plumb from where the scan stopped,
# cut the wall beyond them, -0.27 % (tuning seed 1324). A ring wider than
# a vessel's lip caps only where the wall below shows an outer wall at its
# edge (strays 100-560 mm out showed one: core/surface/surface_model.cpp,
# kOuterMaxBeyondMm).
sweep_args="--family bulge --condition nominal" measure 151 1324
[ "$status" = PV_OK ] && within 0.1 || fail "1324/151 (bulge under a narrow ground): $status $check $volume cm3 against $exact"
# And a vessel's top can be as wide: a grooved bowl vessel's top reaches
# out over its grooves to the outer wall, 28.5 mm; left uncapped as a
# ground, its outer wall read as ground over the mouth: refused OVER_MOUTH
# (fresh seed 1330, looked at for this). Its outer wall under the top caps
# it as a vessel's: -0.22 %.
sweep_args="--family bowl --condition grooves" measure 133 1330
measured_inside "1330/133 (grooved vessel, a top as wide as a ground)"
# A 1.9 L necking pit with ground scanned 26 passes: the wall under its
# neck hidden all round, multipath floating there (the floor's, seen
# through the neck) filled a quarter of those bins, and the band was
# bridged from it up to 20 mm inside the wall: -14.9 % against +/- 9.5 %,
# its single pass -9.0 % (fresh seed 1331, then looked at for this).
# Sparse bins about the neck's radius under a neck are not wall
# (core/surface/surface_model.cpp, reject_fog_under_necks).
sweep_args="--family necking --condition long" twin_within 113 1331 2 ||
  fail "1331/113: $v_case cm3 scanned long against its single pass's $v_twin cm3"
measured_inside "1331/113 (long scan, multipath under a neck)"
# A 0.45 m3 cylinder dug into a 4.1 deg slope: levelled on its ground,
# its floor is a ramp 60 mm high, and the floor store keeps about a point
# per cell of it. Flooded from its lowest cells the floor stopped 8 mm up
# the ramp, and the void under z = 0 was lost: -0.62 % against +/- 0.40 %
# (tuning seed 1334). Seeded above the levelling's floor plane, the whole
# ramp is floor (core/surface/floor_map.cpp, flood_floor).
sweep_args="--family cylinder --condition ground_tilt" measure 786 1334
measured_inside "1334/786 (0.45 m3 cylinder in a 4 deg slope)"
# A 1.1 L rounded bowl with ground, scanned 4.5 deg off: its floor fit
# 35-40 deg off, the ground too steep to be found from there, and the
# support plane (which turns at most 30 deg from its start) 39.7 deg from
# the scanner: the wall's bins across that tilt thick, refused DOUBLED_WALL
# (0.79; the 8-pass scan 0.37, fresh seed 1339). The ground seen from the
# scanner's axis is the opening (core/session/level_surface.cpp,
# level_opening): +0.10 % and +0.07 %.
keep=1 sweep_args="--family rounded_bowl --condition long" measure 555 1339
measured_inside "1339/555 (8 passes over a rounded bowl)"
twin=1 sweep_args="--family rounded_bowl --condition long" measure 555 1339
measured_inside "1339/555 single pass (a rounded bowl)"
# A "ground" under the pit's top, the wall seen going on above it all
# round: a grooved bowl without surround levelled on a groove's ledge 17 mm
# under its rim (tuning seed 1334), a protrusion pit scanned over an arc
# on a block's top 11 mm under it (fresh seed 1339), both refused
# PV_ERR_NO_RIM. Levelled again without grounds, on the rim plane
# (core/session/measure.cpp, surface_in_frame): +0.02 % and +0.05 %.
sweep_args="--family bowl --condition grooves" measure 79 1334
measured_inside "1334/079 (a grooved bowl without surround)"
sweep_args="--family protrusions --condition arc" measure 509 1339
measured_inside "1339/509 (a protrusion pit scanned over an arc)"
# The same from the scanner's axis: a 1.2 L hand-dug pit without surround
# held 24 deg off, its floor fit upside down, the axis's "ground" 13 mm
# over its bottom, refused PV_ERR_NO_RIM (fresh seed 1340, the table's);
# from the axis without grounds, on its rim plane: -0.01 %.
sweep_args="--family hand_dug --condition nominal" measure 803 1340
measured_inside "1340/803 (a hand-dug pit held 24 deg off)"
# A 0.86 L protrusion pit scanned 26 passes: the wall in its blocks'
# shadows bridged from the blocks' faces, 2-11 mm inside the wall, -0.97 %
# (its single pass +0.04 %). Bridged halfway out to the wall beside the
# blocks (core/surface/surface_model.cpp, side_reach): -0.72 % (tuning
# seed 1334).
sweep_args="--family protrusions --condition long" measure 692 1334
[ "$status" = PV_OK ] && within 0.8 || fail "1334/692 (26 passes over a protrusion pit): $status $volume cm3 against $exact"
# A 1.3 L rounded bowl: its floor carried flat from where the flood
# stopped to the wall, void where its curve rises, +0.23 %. Rising on
# for 4 mm (floor_rise_at_end): +0.08 % (tuning seed 1334).
sweep_args="--family rounded_bowl --condition nominal" measure 37 1334
[ "$status" = PV_OK ] && within 0.15 || fail "1334/037 (a 1.3 L rounded bowl): $status $volume cm3 against $exact"
# Frames levelled on a weak opening, tipped into the rim's unseen part:
# a 0.3 m3 deep narrow pit without surround on a rim plane through 16
# sectors, 17.5 deg off its floor, +13.5 % against +/- 6.2 % with PV_OK
# (fresh seed 1343, the table's); a rounded bowl vessel whose lip was seen
# over 70 deg on a support plane 9 deg off, +27.9 % against +/- 8.5 %
# (fresh seed 1344); a rounded bowl held 52 deg off on a support plane 27
# deg off, refused DOUBLED_WALL (1343). The pit's axis leans 0.23, 0.20
# and 0.33 in them: refused PV_ERR_NO_RIM, and levelled from the later
# starts (core/session/measure_surface.cpp, kMaxWeakFrameLean): the turned
# axis finds the bowls' lip and ground.
sweep_args="--family deep_narrow --condition nominal" measure 198 1343
[ "$status" = PV_ERR_NO_RIM ] || fail "1343/198 (a rim plane through part of the rim): $status $volume +/- $interval cm3 against $exact"
sweep_args="--family rounded_bowl --condition tilted" measure 785 1344
measured_inside "1344/785 (a support plane on a lip seen over 70 deg)"
sweep_args="--family rounded_bowl --condition tilted" measure 697 1343
measured_inside "1343/697 (a support plane 27 deg off a rounded bowl)"
# A 1.07 m shallow container scanned 22 deg off, no ground: the floor
# plane's frame found its rim plane facing sideways, the scanner's axis
# only the support plane, resting on part of its 8 mm lip and a stray,
# 0.34 deg off the lip: the rim 1.5 mm under the lid's mean, -1.28 %
# against +/- 0.52 % with PV_OK (tuning seed 1334). From the support
# plane's frame the rim plane, within 3 deg of it, is the opening
# (core/session/level_surface.cpp, rim_plane_over_support): -0.21 %.
sweep_args="--family shallow_wide --condition nominal" measure 307 1334
measured_inside "1334/307 (a support plane on part of a container's lip)"
# A 1.5 L deep pit with ground whose second pass slipped 9.7 mm sideways:
# each copy's wall mostly beyond the other's ghost window, the pooled
# blocks' contrast 0.176 under the bins' 0.2: +3.6 % against +/- 3.4 %
# with PV_OK (fresh seed 1346, the table's). The blocks' own limit, 0.1
# (core/session/measure_surface.cpp, kMaxPooledGhostContrast): refused.
sweep_args="--family deep_narrow --condition slip_lateral" measure 437 1346
refused_by DOUBLED_WALL "1346/437 (a small pit slipped 9.7 mm sideways)"
# Passes slipped sideways past the ghost window, the other pass's wall
# apart from the model's by the shift times |cos| of the angle to it, over
# a floor the cut-off leaves at the sectors across
# (core/session/measure_surface.cpp, kMaxShiftOffsetFit): a 1.2 L hand-dug
# pit with ground slipped 20.8 mm, the model the copies' union (+16.6 %
# against +/- 5.0 % with PV_OK), and a 0.52 m3 textured pit read as a
# vessel slipped 13.2 mm, the model their intersection (-1.8 % against
# +/- 0.7 %), fresh seed 1347 (looked at for this). Their single passes
# measure.
sweep_args="--family hand_dug --condition slip_lateral" keep=1 measure 37 1347
refused_by SHIFTED_WALL "1347/037 (a 1.2 L pit slipped 20.8 mm sideways)"
sweep_args="--family hand_dug --condition slip_lateral" twin=1 measure 37 1347
measured_inside "1347/037-1x (its single pass)"
sweep_args="--family textured --condition slip_lateral" keep=1 measure 21 1347
refused_by SHIFTED_WALL "1347/021 (a 0.52 m3 pit slipped 13.2 mm sideways)"
sweep_args="--family textured --condition slip_lateral" twin=1 measure 21 1347
measured_inside "1347/021-1x (its single pass)"
echo "envelope findings: 95 cases as expected"
