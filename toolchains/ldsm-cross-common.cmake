# Shared part of the ARM toolchain files (aarch64-linux-gnu.cmake, arm-linux-gnueabihf.cmake):
# Debian's cross compilers, a target sysroot made by toolchains/prepare-sysroot.sh, pkg-config
# pointed into it, and qemu-user as the emulator so that ctest (and GoogleTest's test discovery)
# run the cross-built executables. Expects LDSM_CROSS_TRIPLET, LDSM_CROSS_ARCH (the sysroot folder
# name) and LDSM_CROSS_QEMU from the including file.
#
# The sysroot is, in order: -DLDSM_SYSROOT=..., $LDSM_SYSROOT, or
# ${LDSM_CROSS_CACHE:-$HOME/.cache/ldsm-cross}/<arch> (prepare-sysroot.sh's default).
set(CMAKE_SYSTEM_NAME Linux)

if(NOT LDSM_SYSROOT)
  if(DEFINED ENV{LDSM_SYSROOT})
    set(LDSM_SYSROOT "$ENV{LDSM_SYSROOT}")
  elseif(DEFINED ENV{LDSM_CROSS_CACHE})
    set(LDSM_SYSROOT "$ENV{LDSM_CROSS_CACHE}/${LDSM_CROSS_ARCH}")
  else()
    set(LDSM_SYSROOT "$ENV{HOME}/.cache/ldsm-cross/${LDSM_CROSS_ARCH}")
  endif()
endif()
set(LDSM_SYSROOT "${LDSM_SYSROOT}" CACHE PATH "Target sysroot (toolchains/prepare-sysroot.sh)")
if(NOT EXISTS "${LDSM_SYSROOT}/usr/lib/${LDSM_CROSS_TRIPLET}")
  message(FATAL_ERROR "No ${LDSM_CROSS_TRIPLET} sysroot at '${LDSM_SYSROOT}': run "
          "toolchains/prepare-sysroot.sh ${LDSM_CROSS_ARCH} or set LDSM_SYSROOT")
endif()
# try_compile() projects re-read this file: hand them the sysroot too.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES LDSM_SYSROOT)

# GCC 12 for ARM (not for x86-64) reports "potential null pointer dereference" inside inlined
# libstdc++ code (a std::vector<std::string> copy-assignment at -O3): a known false positive of
# -Wnull-dereference. It stays a warning; every other warning is still an error with LDSM_WERROR.
if(NOT CMAKE_CXX_FLAGS_INIT MATCHES "null-dereference")  # this file is read more than once
  string(APPEND CMAKE_CXX_FLAGS_INIT " -Wno-error=null-dereference")
endif()

set(CMAKE_C_COMPILER ${LDSM_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${LDSM_CROSS_TRIPLET}-g++)
set(CMAKE_SYSROOT "${LDSM_SYSROOT}")
set(CMAKE_LIBRARY_ARCHITECTURE ${LDSM_CROSS_TRIPLET})

# Libraries, headers and CMake packages from the sysroot only; programs (pkg-config...) from the
# host.
set(CMAKE_FIND_ROOT_PATH "${LDSM_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

set(ENV{PKG_CONFIG_SYSROOT_DIR} "${LDSM_SYSROOT}")
set(ENV{PKG_CONFIG_LIBDIR}
    "${LDSM_SYSROOT}/usr/lib/${LDSM_CROSS_TRIPLET}/pkgconfig:${LDSM_SYSROOT}/usr/lib/pkgconfig:${LDSM_SYSROOT}/usr/share/pkgconfig")
unset(ENV{PKG_CONFIG_PATH})

# Shared libraries that the sysroot's libraries need (DT_NEEDED) are found by the linker in the
# sysroot's library folders.
foreach(kind EXE SHARED MODULE)
  set(CMAKE_${kind}_LINKER_FLAGS_INIT
      "-Wl,-rpath-link,${LDSM_SYSROOT}/usr/lib/${LDSM_CROSS_TRIPLET}:${LDSM_SYSROOT}/lib/${LDSM_CROSS_TRIPLET}")
endforeach()

# Run target executables (ctest, gtest_discover_tests, add_custom_command on targets) with qemu.
find_program(LDSM_CROSS_QEMU_PATH NAMES ${LDSM_CROSS_QEMU} REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR "${LDSM_CROSS_QEMU_PATH};-L;${LDSM_SYSROOT}")
