# Cross-building for arm64 (aarch64) Linux on a Debian amd64 machine, with Debian's cross compiler and the arm64
# builds of the libraries beside the amd64 ones (multiarch: /usr/lib/aarch64-linux-gnu). deploy/install-deps.sh
# --crossmachine installs them; tests/crossmachine/check_arm64.py uses this file:
#
#   cmake -S . -B build/crossmachine/arm64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DPOET_BUILD_PYTHON=OFF -DPOET_BUILD_BENCH=OFF
#   cmake --build build/crossmachine/arm64 -j2 --target poet-worker poet-coordinator poet_unit_tests
#
# protoc is the host's (the same protobuf 3.21 generates the code for both). The build runs two of its arm64
# programs, poet-schema-defaults (proto/) and the tests' listing (gtest_discover_tests), through qemu's user-mode
# emulator: CMAKE_CROSSCOMPILING_EMULATOR, also how ctest would start the arm64 tests.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# the multiarch directories: libraries in /usr/lib/aarch64-linux-gnu, CMake packages in its cmake/ and pkgconfig/
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Programs (protoc, pkg-config) are the host's; libraries, headers and CMake packages are searched in / with the
# architecture's directories first, never in the amd64 ones (CMake searches lib/<CMAKE_LIBRARY_ARCHITECTURE>).
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

# pkg-config (cairo, libmicrohttpd, cpp-httplib) reads the arm64 .pc files only, and the arch-independent ones
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
unset(ENV{PKG_CONFIG_PATH})

# arm64 programs the build runs: qemu-aarch64-static, the loader and libraries from / (libc6:arm64 and the others)
find_program(POET_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64)
if(POET_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR "${POET_QEMU_AARCH64};-L;/")
else()
  message(WARNING "qemu-aarch64-static is not installed (deploy/install-deps.sh --crossmachine): the build cannot run "
                  "poet-schema-defaults, an arm64 program")
endif()
