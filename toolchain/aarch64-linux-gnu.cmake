# The board: aarch64 Linux (Debian's cross compiler g++-aarch64-linux-gnu).
# Tests run under qemu-user through CTest (CMAKE_CROSSCOMPILING_EMULATOR).
# Target libraries come from Debian's arm64 multiarch packages
# (/usr/lib/aarch64-linux-gnu, e.g. libcmocka-dev:arm64); header-only
# libraries (Eigen) come from the host's /usr/share. See docs/targets.md.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

# pkg-config sees the arm64 .pc files only: a library that is installed for
# the host but not for the board (libusb, umockdev) is "not found".
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

# -L: the target's dynamic loader and libc; the arm64 multiarch libraries in
# /usr/lib/aarch64-linux-gnu are found by their real path.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static -L /usr/aarch64-linux-gnu)
