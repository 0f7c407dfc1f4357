#!/usr/bin/env bash
# The Debian packages (label package, packaging/CMakeLists.txt): cpack makes
# the package from the build, it is unpacked into a scratch root (dpkg -x:
# nothing is installed) and what it installed is run from there.
#
#   test_packages.sh host  BUILD_DIR WORK_DIR SAMPLE_PLY
#     pitvol_VERSION_amd64.deb: the installed pitvol measures the sample
#     scan to the bit of the build's own; every Depends is installed here.
#   test_packages.sh board BUILD_DIR WORK_DIR SYSROOT SOURCE_DIR RUNNER...
#     pitvol-board_VERSION_arm64.deb: an aarch64 pitvol-board, its systemd
#     unit and /etc/pitvol/board.conf as a conffile; every library it needs
#     is in Depends (looked up in the sysroot's packages); `pitvol-board
#     --help` under qemu (RUNNER); the unit passes systemd-analyze verify;
#     the installed program with the installed board.conf runs under the
#     service protocol (tests/packaging/test_watchdog.py).
set -euo pipefail
kind=$1 build=$2 work=$3
shift 3
fail() { echo "FAIL [$kind]: $*" >&2; exit 1; }
pass() { echo "ok   [$kind]: $*"; }

rm -rf "$work"
mkdir -p "$work"
(cd "$build" && "${CPACK:-cpack}" -B "$work/out" >"$work/cpack.log" 2>&1) || fail "cpack: $(tail -5 "$work/cpack.log")"
debs=("$work"/out/*.deb)
[ ${#debs[@]} -eq 1 ] && [ -f "${debs[0]}" ] || fail "want one .deb, got: ${debs[*]}"
deb=${debs[0]}
root=$work/root
dpkg-deb -x "$deb" "$root"
field() { dpkg-deb -f "$deb" "$1"; }
has_file() { dpkg-deb -c "$deb" | awk '{print $NF}' | grep -qx "./$1" || fail "$(basename "$deb") lacks /$1"; }
pass "$(basename "$deb"): $(dpkg-deb -c "$deb" | grep -c '^-') files, Depends: $(field Depends)"

case $kind in
host)
  sample=$1
  [ "$(field Package)" = pitvol ] && [ "$(field Architecture)" = amd64 ] || fail "package $(field Package) $(field Architecture)"
  for p in pitvol pitvol-monitor pitvol-sim pitvol-accuracy pitvol-synth; do has_file "usr/bin/$p"; done
  # Each dependency is a package name, optionally with a version: installed here.
  field Depends | tr ',' '\n' | sed 's/(.*//; s/ //g' | while read -r dep; do
    dpkg-query -W -f='${Status}' "$dep" 2>/dev/null | grep -q "install ok installed" ||
      fail "Depends $dep is not installed on this host"
  done
  ! readelf -d "$root/usr/bin/pitvol" | grep -Eq 'RPATH|RUNPATH' || fail "installed pitvol keeps a build RPATH"
  want=$("$build/bin/pitvol" measure "$sample" --json | sed -n 's/.*"volume_cm3": \([^,]*\),.*/\1/p')
  got=$("$root/usr/bin/pitvol" measure "$sample" --json | sed -n 's/.*"volume_cm3": \([^,]*\),.*/\1/p')
  [ -n "$want" ] && [ "$got" = "$want" ] || fail "installed pitvol measured '$got', the build's $want"
  pass "installed pitvol measures the sample: $got cm3, the build's bits"
  "$root/usr/bin/pitvol-monitor" --help >"$work/monitor.txt" 2>&1 || true
  grep -q "usage: pitvol-monitor" "$work/monitor.txt" || fail "pitvol-monitor --help: $(head -3 "$work/monitor.txt")"
  pass "installed pitvol-monitor runs"
  ;;
board)
  sysroot=$1 source=$2
  shift 2
  runner=("$@")
  [ "$(field Package)" = pitvol-board ] && [ "$(field Architecture)" = arm64 ] || fail "package $(field Package) $(field Architecture)"
  has_file usr/bin/pitvol-board
  has_file usr/lib/systemd/system/pitvol-board.service
  has_file etc/pitvol/board.conf
  has_file usr/lib/udev/rules.d/60-pitvol-scanner.rules
  dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles | grep -qx /etc/pitvol/board.conf ||
    fail "/etc/pitvol/board.conf is not a conffile"
  readelf -h "$root/usr/bin/pitvol-board" | grep -q "Machine: *AArch64" || fail "pitvol-board is not aarch64"
  pass "aarch64 pitvol-board, systemd unit, udev rule; /etc/pitvol/board.conf a conffile"
  # Every shared library pitvol-board needs comes from a package it Depends on.
  deps=" $(field Depends | tr ',' '\n' | sed 's/(.*//; s/ //g' | tr '\n' ' ') "
  for lib in $(readelf -d "$root/usr/bin/pitvol-board" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
    owner=
    for d in "$sysroot"/../debs/*.deb; do
      # The path is the last field, or the one before "-> target" for a link.
      if dpkg-deb -c "$d" | awk -v want="/$lib" '{ p = ($(NF-1) == "->") ? $(NF-2) : $NF;
           if (substr(p, length(p) - length(want) + 1) == want) found = 1 } END { exit !found }'; then
        owner=$(dpkg-deb -f "$d" Package)
        break
      fi
    done
    [ -n "$owner" ] || fail "no sysroot package holds $lib"
    [[ $deps == *" $owner "* ]] || fail "pitvol-board needs $lib from $owner, not in Depends:$deps"
  done
  pass "every library pitvol-board needs is in Depends"
  "${runner[@]}" "$root/usr/bin/pitvol-board" --help >"$work/help.txt" 2>&1 || true
  grep -q "usage: pitvol-board" "$work/help.txt" || fail "pitvol-board --help under qemu: $(head -3 "$work/help.txt")"
  pass "installed pitvol-board --help under qemu-aarch64"
  unit=$root/usr/lib/systemd/system/pitvol-board.service
  grep -qx "Restart=on-failure" "$unit" && grep -qx "Type=notify" "$unit" && grep -q "^WatchdogSec=[1-9]" "$unit" ||
    fail "the unit lacks Restart=on-failure, Type=notify or WatchdogSec"
  grep -qx "ExecStart=/usr/bin/pitvol-board --config /etc/pitvol/board.conf" "$unit" || fail "ExecStart"
  # systemd-analyze checks that ExecStart's program exists: the copy it
  # verifies points into the scratch root. It exits 0 on the warnings it
  # prints, so any output fails the test.
  mkdir -p "$work/verify"
  sed "s|^ExecStart=/usr/bin/|ExecStart=$root/usr/bin/|" "$unit" >"$work/verify/pitvol-board.service"
  systemd-analyze verify "$work/verify/pitvol-board.service" >"$work/verify.txt" 2>&1 ||
    fail "systemd-analyze verify: $(cat "$work/verify.txt")"
  [ ! -s "$work/verify.txt" ] || fail "systemd-analyze verify: $(cat "$work/verify.txt")"
  pass "systemd-analyze verify: the unit is clean"
  /usr/bin/python3 "$source/tests/packaging/test_watchdog.py" "$work/watchdog" "${runner[@]}" \
    "$root/usr/bin/pitvol-board" --config "$root/etc/pitvol/board.conf" || fail "watchdog"
  pass "the installed pitvol-board with the installed board.conf under the service protocol"
  ;;
*)
  fail "unknown kind" ;;
esac
