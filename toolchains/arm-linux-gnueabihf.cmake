# Cross-compiling ldsm for 32-bit ARMv7 with NEON (Raspberry Pi 2/3 with a 32-bit OS, i.MX6,
# older boards) with Debian's arm-linux-gnueabihf-g++ and a Debian bookworm armhf sysroot:
#   bash toolchains/prepare-sysroot.sh armhf
#   cmake -S . -B build-armhf -G Ninja -DCMAKE_TOOLCHAIN_FILE=toolchains/arm-linux-gnueabihf.cmake
# Debian's armhf baseline is ARMv7-A with VFPv3-D16 and no NEON: -mfpu=neon turns NEON on (the
# board must have it). ARMv7 NEON lacks AArch64's across-vector reductions (vaddvq_f32...): the
# kernels use pairwise adds there. -Wno-psabi silences GCC's note that the ABI of passing some
# structures changed in GCC 7.1 (irrelevant when everything is built with one compiler).
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(LDSM_CROSS_TRIPLET arm-linux-gnueabihf)
set(LDSM_CROSS_ARCH armhf)
set(LDSM_CROSS_QEMU qemu-arm-static)
set(CMAKE_C_FLAGS_INIT "-march=armv7-a -mfpu=neon -mfloat-abi=hard")
set(CMAKE_CXX_FLAGS_INIT "-march=armv7-a -mfpu=neon -mfloat-abi=hard -Wno-psabi")
include(${CMAKE_CURRENT_LIST_DIR}/ldsm-cross-common.cmake)
