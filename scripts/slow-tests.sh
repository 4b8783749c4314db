#!/usr/bin/env bash
# Prints a ctest -E alternation ("A\.b|C\.d") of the tests that took longer than SECONDS in the
# native suite's last run, read from that build's CTestCostData.txt; prints nothing when there
# is no such file. Used by the jobs that run the suite much slower than natively (cross-test.sh
# under qemu, sanitize.sh) to leave long whole-SLAM runs to the native suite.
# Usage: scripts/slow-tests.sh SECONDS [NATIVE_BUILD_DIR (default: build)]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:?usage: slow-tests.sh SECONDS [NATIVE_BUILD_DIR]}
costs=${2:-build}/Testing/Temporary/CTestCostData.txt
[ -f "$costs" ] || exit 0
awk -v m="$seconds" '/^---/ {exit} NF >= 3 && $3 + 0 > m {print $1}' "$costs" |
  sed 's/[][\\.^$*+?(){}|]/\\&/g' | paste -sd'|' -
