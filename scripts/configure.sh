#!/usr/bin/env bash
# Configures the build folder with every option set explicitly, whatever an earlier configure
# cached: the README's two commands (demo.sh, run-tests.sh) share one configuration, so they work
# in either order and repeated, and neither can inherit a switched-off test or benchmark build.
# Usage: scripts/configure.sh BUILD_DIR [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:?usage: configure.sh BUILD_DIR [cmake args]}
shift
# Options whose default depends on the machine (the ThreadSanitizer tests: x86-64 with GCC or
# Clang) are dropped from the cache so that their default is worked out again.
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DLDSM_BUILD_TESTS=ON -DLDSM_BUILD_BENCH=ON -DLDSM_BUILD_APPS=ON \
      -DLDSM_SIMD=auto -DLDSM_NATIVE=OFF -DLDSM_WERROR=ON \
      -DLDSM_WITH_V4L2=ON -DLDSM_WITH_LIBCAMERA=ON -DLDSM_FUZZ=OFF -ULDSM_TSAN_TESTS "$@"
