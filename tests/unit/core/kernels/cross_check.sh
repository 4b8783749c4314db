#!/bin/sh
# Builds the SIMD tests for the kernels the host build does not use and runs them: NEON with
# cross compilers under qemu-user (AArch64, and ARMv7 hard float with -mfpu=neon), and the plain
# C++ fallback (LDSM_SIMD=scalar) natively. Compiled as the project is (-ffp-contract=off, see
# cmake/LdsmCompilerFlags.cmake): several kernels must equal their references bit for bit.
# Needs g++-aarch64-linux-gnu, g++-arm-linux-gnueabihf, qemu-user and the GoogleTest sources in
# /usr/src/googletest.
#   tests/unit/core/kernels/cross_check.sh [work dir, default /tmp/ldsm-simd-check]
set -eu
root=$(cd "$(dirname "$0")/../../../.." && pwd)
work=${1:-/tmp/ldsm-simd-check}
gtest=/usr/src/googletest/googletest
mkdir -p "$work"

tests="$root/tests/unit/core/math/vec4f_test.cpp $root/tests/unit/core/kernels/pattern_kernels_test.cpp
  $root/tests/unit/core/kernels/coarse_accumulate_test.cpp
  $root/tests/unit/core/kernels/coarse_warp_test.cpp
  $root/tests/unit/core/frontend/coarse_evaluation_sums_test.cpp
  $root/tests/unit/core/camera/remap_bilinear_test.cpp
  $root/tests/unit/core/kernels/evaluate_residual_test.cpp
  $root/tests/unit/core/kernels/pattern_energy_test.cpp
  $root/tests/unit/core/image/threshold_row_test.cpp"
sources="$root/core/src/backend/photometric_residual.cpp $root/core/src/backend/active_point.cpp
  $root/core/src/image/image_pyramid.cpp $root/core/src/image/compact_plane.cpp
  $root/core/src/frontend/coarse_residuals.cpp"

check() {  # name, compiler, SIMD, runner ("" = native), sysroot, extra flags
  name=$1 cxx=$2 simd=$3 runner=$4 sysroot=$5
  shift 5
  if ! command -v "$cxx" >/dev/null; then
    echo "== $name: SKIPPED, no $cxx"
    return
  fi
  if [ -n "$runner" ] && ! command -v "$runner" >/dev/null; then
    runner="$runner-static"  # Debian's qemu-user-static
    command -v "$runner" >/dev/null || { echo "== $name: SKIPPED, no $runner (qemu-user)"; return; }
  fi
  dir="$work/$name"
  mkdir -p "$dir"
  if [ ! -f "$dir/gtest.a" ]; then
    $cxx -O1 -std=c++17 -isystem "$gtest/include" -I"$gtest" -c "$gtest/src/gtest-all.cc" \
      -o "$dir/gtest-all.o"
    $cxx -O1 -std=c++17 -isystem "$gtest/include" -c "$gtest/src/gtest_main.cc" \
      -o "$dir/gtest_main.o"
    ar rcs "$dir/gtest.a" "$dir/gtest-all.o" "$dir/gtest_main.o"
  fi
  # shellcheck disable=SC2086
  $cxx -O2 -std=c++17 -ffp-contract=off "$@" -Wall -Wextra -Wpedantic -Wshadow=local -Wcast-align -Werror \
    -DLDSM_SIMD_$simd=1 -I"$root/core/include" -I"$root/core/src" -I"$root/tests/support" \
    -isystem /usr/include/eigen3 -isystem "$gtest/include" $tests $sources "$dir/gtest.a" \
    -lpthread -o "$dir/test_simd"
  echo "== $name"
  status=0
  if [ -n "$runner" ]; then
    $runner -L "$sysroot" "$dir/test_simd" > "$dir/log" 2>&1 || status=$?
  else
    "$dir/test_simd" > "$dir/log" 2>&1 || status=$?
  fi
  tail -n 3 "$dir/log"
  if [ "$status" -ne 0 ]; then
    echo "== $name: FAILED (exit status $status, log in $dir/log)"
    failed="$failed $name"
  fi
}
failed=""

check scalar g++ SCALAR "" ""
check aarch64 aarch64-linux-gnu-g++ NEON qemu-aarch64 /usr/aarch64-linux-gnu
check armv7 arm-linux-gnueabihf-g++ NEON qemu-arm /usr/arm-linux-gnueabihf \
  -march=armv7-a -mfpu=neon -mfloat-abi=hard -Wno-psabi
if [ -n "$failed" ]; then
  echo "FAILED:$failed"
  exit 1
fi
