#!/usr/bin/env bash
# Installs the Debian packages pitvol builds and tests with, and only those
# that are missing, so it is cheap to run before every build (idempotent).
# Usage: toolchain/install-deps.sh [--cross] [--peers] [--browser] [extra-package ...]
#   --cross  also the board (aarch64) and MCU (Cortex-M7) toolchains and
#            emulators, cppcheck, clang-tidy, and the arm64 package lists
#            the board's sysroot is downloaded from (docs/targets.md).
#   --peers  also the peer programs of the accuracy report (CloudCompare,
#            about 200 MB; only the `peers` CTest label needs it).
#   --browser  also headless Chromium (about 360 MB), which the `report`
#            CTest label opens the scan report in (docs/report.md).
set -euo pipefail

cross=0
peer_packages=()
browser_packages=()
while [ $# -gt 0 ]; do
  case "$1" in
    --cross) cross=1; shift ;;
    --peers) peer_packages=(cloudcompare); shift ;;
    --browser) browser_packages=(chromium); shift ;;
    *) break ;;
  esac
done

packages=(
  cmake ninja-build pkg-config g++
  libeigen3-dev      # fixed-size linear algebra in the core
  libcmocka-dev      # C unit test framework
  libembree-dev      # ray casting in the scanner simulator (host only)
  libusb-1.0-0-dev   # the scanner's USB driver (drivers/usb)
  umockdev libumockdev-dev  # emulated USB scanner for the usb tests
  libpng-dev            # the board display's PNG backend (drivers/display)
  console-setup-linux   # Terminus console fonts embedded in pitvol-board
  nanopb libnanopb-dev      # serial link messages (lib/link/pitvol_link.proto)
  nlohmann-json3-dev    # the host tools' JSON output and reading (header-only)
  libcli11-dev          # the host tools' command lines (header-only)
  clang-14 libfuzzer-14-dev libclang-rt-14-dev  # fuzz/: libFuzzer + ASan/UBSan runtimes
  "${peer_packages[@]}"
  python3-matplotlib    # pitvol-report's plots (host_tools/report, /usr/bin/python3)
  dpkg-dev systemd      # packages: dpkg-shlibdeps (cpack), systemd-analyze verify of the unit
  "${browser_packages[@]}"
  "$@"
)
if [ $cross -eq 1 ]; then
  packages+=(
    g++-aarch64-linux-gnu qemu-user-static   # board build, tests under qemu-aarch64
    gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib
    qemu-system-arm                          # MCU build, runs on mps2-an500
    cppcheck
    clang-tidy   # toolchain/run-clang-tidy.sh (by hand, not in CI: docs/targets.md)
    # No arm64 package is installed: the board's libraries are unpacked
    # into a sysroot by toolchain/arm64-sysroot.sh, which only needs the
    # arm64 package lists (the architecture is added to dpkg below).
  )
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
if [ $cross -eq 1 ] && ! dpkg --print-foreign-architectures | grep -qx arm64; then
  command -v sudo >/dev/null || [ "$(id -u)" -eq 0 ] ||
    { echo "pitvol: need root or sudo to add the arm64 architecture" >&2; exit 1; }
  echo "pitvol: adding the arm64 architecture to dpkg (package lists for toolchain/arm64-sysroot.sh)" >&2
  "${sudo_cmd[@]}" dpkg --add-architecture arm64
  "${sudo_cmd[@]}" apt-get update -qq
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "pitvol: installing missing packages: ${missing[*]}" >&2
command -v sudo >/dev/null || [ "$(id -u)" -eq 0 ] ||
  { echo "pitvol: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
