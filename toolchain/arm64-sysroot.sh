#!/usr/bin/env bash
# The board's sysroot: Debian's arm64 packages the board build links and
# its tests run with, downloaded (`apt-get download PKG:arm64`) and unpacked
# (`dpkg -x`) into a folder, never installed into the host: arm64 -dev
# packages are Multi-Arch: same with the host's amd64 twins and would pull
# upgrades of the host's systemd and udev libraries.
#
#   toolchain/arm64-sysroot.sh [DIR]     (default: build-sysroot/arm64)
#
# DIR/debs holds the downloaded .deb files (a cache: kept when the package
# list changes, only the missing ones are fetched), DIR/tree the unpacked
# sysroot. The root is rebuilt only when the package list or this script
# changes (DIR/tree/.pitvol-sysroot holds their hash), so a second run
# costs a hash and exits; toolchain/aarch64-linux-gnu.cmake runs it on
# every configure. Needs the arm64 package lists
# (`toolchain/install-deps.sh --cross` adds the architecture); no root.
#
# The root has Debian's merged-/usr layout (lib -> usr/lib), so
# `qemu-aarch64-static -L DIR/tree` finds the dynamic loader at
# /lib/ld-linux-aarch64.so.1 as on the board.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dir=${1:-$here/../build-sysroot/arm64}
mkdir -p "$dir/debs"
dir=$(cd "$dir" && pwd)

# Header-only libraries of the host tools (JSON, command lines): packages
# of Architecture: all, downloaded without ":arm64" (apt has no arm64
# candidate for them). From the sysroot, not the host: their CMake files
# would add the host's /usr/include, which a cross compile must not search.
arch_all=(nlohmann-json3-dev libcli11-dev)
packages=(
  # The C and C++ runtime the programs run with under qemu (-L tree).
  libc6 libgcc-s1 libstdc++6 gcc-12-base
  libusb-1.0-0-dev libusb-1.0-0 libudev1     # the scanner's libusb driver
  libpng-dev libpng16-16 zlib1g-dev zlib1g   # the display's PNG backend
  libnanopb-dev                              # the serial link's messages
  libcmocka-dev libcmocka0                   # unit tests
  # The emulated scanner (pitvol-board-emu, the e2e tests): umockdev's
  # library and its LD_PRELOAD library, GLib and what they load.
  libumockdev-dev libumockdev0 umockdev libpcap0.8 libdbus-1-3 libsystemd0
  libcap2 libgcrypt20 libgpg-error0 liblz4-1 liblzma5 libzstd1
  libglib2.0-dev libglib2.0-0 libmount1 libblkid1 libselinux1
  libffi-dev libffi8 libpcre2-dev libpcre2-8-0 libpcre2-16-0 libpcre2-32-0 libpcre2-posix3  # GLib's .pc files name them
  "${arch_all[@]}"
)

stamp_text=$(printf '%s\n' "${packages[@]}" | cat - "$0" | sha256sum | cut -d' ' -f1)
[ "$(cat "$dir/tree/.pitvol-sysroot" 2>/dev/null)" = "$stamp_text" ] && exit 0

exec 9>"$dir/.lock"
flock 9
# Another run may have built it while this one waited for the lock.
[ "$(cat "$dir/tree/.pitvol-sysroot" 2>/dev/null)" = "$stamp_text" ] && exit 0

if ! apt-cache show libc6:arm64 >/dev/null 2>&1; then
  echo "pitvol: no arm64 package lists; run toolchain/install-deps.sh --cross (it adds the arm64" \
       "architecture to dpkg and updates the lists; nothing arm64 is installed)" >&2
  exit 1
fi

cd "$dir/debs"
missing=()
for p in "${packages[@]}"; do
  compgen -G "${p}_*_arm64.deb" >/dev/null || compgen -G "${p}_*_all.deb" >/dev/null && continue
  if [[ " ${arch_all[*]} " == *" $p "* ]]; then missing+=("$p"); else missing+=("$p:arm64"); fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "pitvol: downloading ${#missing[@]} arm64 packages into $dir/debs" >&2
  apt-get download -q "${missing[@]}" >&2
fi

rm -rf "$dir/tree.new"
mkdir -p "$dir/tree.new"
for p in "${packages[@]}"; do
  # The newest file of a package, should the cache hold two versions.
  deb=$(ls -t $(compgen -G "${p}_*_arm64.deb"; compgen -G "${p}_*_all.deb") | head -1)
  dpkg -x "$deb" "$dir/tree.new"
done
cd "$dir/tree.new"
# Merged /usr, as a bookworm system: lib/ and lib64/ into usr/.
for d in lib lib64; do
  if [ -d "$d" ] && [ ! -L "$d" ]; then
    mkdir -p "usr/$d"
    cp -a "$d/." "usr/$d/"
    rm -rf "$d"
  fi
  ln -sfn "usr/$d" "$d"
done
# Absolute symlinks (libfoo.so -> /lib/...) point into the host: make them
# relative to the root.
find . -type l -lname '/*' | while read -r link; do
  target=$(readlink "$link")
  ln -sfn "$(realpath -m --relative-to="$(dirname "$link")" ".$target")" "$link"
done
echo "$stamp_text" >.pitvol-sysroot
cd "$dir"
rm -rf tree
mv tree.new tree
echo "pitvol: arm64 sysroot ready in $dir/tree" >&2
