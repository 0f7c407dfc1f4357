#!/usr/bin/env bash
# Installs the Debian packages pitvol builds and tests with, and only those
# that are missing, so it is cheap to run before every build (idempotent).
# Usage: toolchain/install-deps.sh [--peers] [extra-package ...]
#   --peers: also the peer programs of the accuracy report (CloudCompare,
#            about 200 MB; only the `peers` CTest label needs it).
set -euo pipefail

peer_packages=()
if [ "${1:-}" = "--peers" ]; then
  shift
  peer_packages=(cloudcompare)
fi

packages=(
  cmake ninja-build pkg-config g++
  libeigen3-dev      # fixed-size linear algebra in the core
  libnanoflann-dev   # kNN for adaptive thinning
  libcmocka-dev      # C unit test framework
  libembree-dev      # ray casting in the scanner simulator (host only)
  libusb-1.0-0-dev   # the scanner's USB driver (drivers/usb)
  umockdev libumockdev-dev  # emulated USB scanner for the usb tests
  "${peer_packages[@]}"
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "pitvol: installing missing packages: ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "pitvol: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
