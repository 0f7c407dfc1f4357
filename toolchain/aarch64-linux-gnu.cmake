# The board: aarch64 Linux (Debian's cross compiler g++-aarch64-linux-gnu).
# Target libraries come from a sysroot of Debian's arm64 packages, unpacked
# (not installed) by toolchain/arm64-sysroot.sh, which this file runs: the
# first configure downloads them, later ones find them cached. Header-only
# and data packages (Eigen, the console fonts) come from the host.
# Tests run under qemu-user through CTest (CMAKE_CROSSCOMPILING_EMULATOR)
# with the sysroot's loader and libraries. See docs/targets.md.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# The environment variable, not a cache entry: try_compile projects read
# this file again and see the environment, not the cache.
if(DEFINED ENV{PITVOL_ARM64_SYSROOT})
  set(pv_sysroot_dir $ENV{PITVOL_ARM64_SYSROOT})
else()
  get_filename_component(pv_sysroot_dir ${CMAKE_CURRENT_LIST_DIR}/../build-sysroot/arm64 ABSOLUTE)
endif()
execute_process(COMMAND ${CMAKE_CURRENT_LIST_DIR}/arm64-sysroot.sh ${pv_sysroot_dir}
                RESULT_VARIABLE pv_sysroot_rc)
if(NOT pv_sysroot_rc EQUAL 0)
  message(FATAL_ERROR "toolchain/arm64-sysroot.sh failed: no arm64 sysroot in ${pv_sysroot_dir}")
endif()
set(PITVOL_SYSROOT ${pv_sysroot_dir}/tree)

# The compiler's own C library (/usr/aarch64-linux-gnu) and the sysroot's
# packages; never the host's /usr/lib/aarch64-linux-gnu, whatever multiarch
# packages it has.
set(CMAKE_FIND_ROOT_PATH ${PITVOL_SYSROOT} /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)  # Eigen's config is the host's

set(ENV{PKG_CONFIG_LIBDIR} "${PITVOL_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${PITVOL_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${PITVOL_SYSROOT}")
set(ENV{PKG_CONFIG_PATH} "")

# The linker finds the libraries the sysroot's libraries need (libusb ->
# libudev, umockdev -> GLib) there.
set(pv_rpath_link "-Wl,-rpath-link,${PITVOL_SYSROOT}/usr/lib/aarch64-linux-gnu")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${pv_rpath_link}")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "${pv_rpath_link}")

# Programs run under qemu-user through the sysroot's dynamic loader, which
# takes its libraries from the sysroot only (--library-path). Not
# `qemu-aarch64-static -L SYSROOT`: -L maps every path that exists in the
# sysroot there, "/" included, and umockdev's LD_PRELOAD library resolves
# paths relative to a directory descriptor by reading /proc/self/fd; with
# "/" opened as the sysroot, libudev's walk from "/" to /sys misses the
# test bed and the emulated scanner is never seen (docs/targets.md).
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static ${PITVOL_SYSROOT}/lib/ld-linux-aarch64.so.1
    --library-path ${PITVOL_SYSROOT}/usr/lib/aarch64-linux-gnu)
