#!/usr/bin/env bash
# The README's test command: installs what is needed (apt), builds ldsm with every test, and runs
# the whole test suite. Tests that need ../shared/data skip with a message when it is absent.
#
# Before the tests it prints the machine (CPU, cores the process may use, the cgroup's CPU quota);
# after them the slowest tests, so that a slow or failing CI run says where its time went.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-$(bash scripts/cpu-count.sh)}
bash scripts/configure.sh "$BUILD_DIR"
cmake --build "$BUILD_DIR" -j "$JOBS"

echo "run-tests: $(bash scripts/cpu-count.sh --describe); running $JOBS tests at a time"
# ctest starts the longest tests first when it knows their times: on a fresh build folder it is
# given the times measured for the suite (tests/ctest-costs.txt), so that the long system tests
# do not end up last, one core idle while the other finishes them.
costs="$BUILD_DIR/Testing/Temporary/CTestCostData.txt"
if [ ! -s "$costs" ] && [ -f tests/ctest-costs.txt ]; then
  mkdir -p "$(dirname "$costs")"
  cp tests/ctest-costs.txt "$costs"
fi
start=$(date +%s)
rc=0
ctest --test-dir "$BUILD_DIR" --output-on-failure --no-tests=error -j "$JOBS" --timeout 900 || rc=$?
echo "run-tests: ctest took $(($(date +%s) - start)) s (exit code $rc); the slowest tests:"
awk '/^[0-9]+\/[0-9]+ Testing: /{name=$3} /^Test time = /{printf "%10.2f s  %s\n", $4, name}' \
  "$BUILD_DIR/Testing/Temporary/LastTest.log" | sort -rn | head -15 || true
exit "$rc"
