# Cross-compiling ldsm for 64-bit ARM (Raspberry Pi 4/5 with a 64-bit OS, Jetson, i.MX8) with
# Debian's aarch64-linux-gnu-g++ and a Debian bookworm arm64 sysroot:
#   bash toolchains/prepare-sysroot.sh aarch64
#   cmake -S . -B build-aarch64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=toolchains/aarch64-linux-gnu.cmake
# ctest runs the tests with qemu-aarch64-static. LDSM_SIMD=auto picks the NEON kernels (AArch64
# has NEON and the across-vector reductions such as vaddvq_f32 in its base instruction set).
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(LDSM_CROSS_TRIPLET aarch64-linux-gnu)
set(LDSM_CROSS_ARCH aarch64)
set(LDSM_CROSS_QEMU qemu-aarch64-static)
include(${CMAKE_CURRENT_LIST_DIR}/ldsm-cross-common.cmake)
