# Cross-compiling for 64-bit ARM Linux with Debian's GNU cross toolchain (g++-aarch64-linux-gnu and
# libc6-dev-arm64-cross, which installs the target's C library under /usr/aarch64-linux-gnu).
#
#   cmake -S . -B build/aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake ...
#
# Only the runtime and its tests cross-build (-DDNG_BUILD_BAKER=OFF): there are no aarch64 builds of the
# baker's libraries here. `bash setup.sh aarch64` does the whole thing; docs/CONTRIBUTING.md explains.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(DNG_CROSS_TRIPLE aarch64-linux-gnu)
set(DNG_CROSS_ROOT /usr/${DNG_CROSS_TRIPLE})
set(CMAKE_C_COMPILER ${DNG_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${DNG_CROSS_TRIPLE}-g++)

# Libraries, headers and CMake packages come from the target's root only, never from the host's
# x86-64 /usr/lib; programs (ninja, sh, pkg-config) come from the host. A package built for aarch64
# elsewhere (GoogleTest, by setup.sh) is named by its <Package>_DIR, which is used as given.
list(APPEND CMAKE_FIND_ROOT_PATH ${DNG_CROSS_ROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# pkg-config would otherwise offer the host's .pc files (libxxhash) and link x86-64 libraries.
set(ENV{PKG_CONFIG_LIBDIR} ${DNG_CROSS_ROOT}/lib/pkgconfig)

# ctest and gtest_discover_tests run the test programs through qemu-user; -L points its ELF loader at
# the target's C library. Without qemu the build still works, only the tests cannot run.
find_program(DNG_QEMU_AARCH64 NAMES qemu-aarch64 qemu-aarch64-static)
if(DNG_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${DNG_QEMU_AARCH64} -L ${DNG_CROSS_ROOT})
endif()
