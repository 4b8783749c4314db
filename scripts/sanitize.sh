#!/usr/bin/env bash
# Builds the whole test suite with sanitizers and runs it (docs/reliability.md):
#
#   bash scripts/sanitize.sh            # address: AddressSanitizer + UndefinedBehaviorSanitizer
#   bash scripts/sanitize.sh thread     # ThreadSanitizer, the threaded system and pipeline tests
#   bash scripts/sanitize.sh all        # both, one after the other
#
# Each kind builds in its own folder (build-asan, build-tsan; BUILD_ROOT changes the prefix) with
# line tables and the optimiser on (-O1 -g1), so that reports name files and lines. Any report
# fails the run: UBSan and ASan halt on the first error, LeakSanitizer reports at exit, TSan exits
# with status 66. Tests that need the machine's real speed (real-time replay) are left out, as
# under qemu: a sanitized build is 20-50x slower, so most of their frames are dropped by design;
# so are the long whole-SLAM runs (scripts/slow-tests.sh).
# Environment: JOBS (default scripts/cpu-count.sh), SANITIZE_EXCLUDE (a ctest -E regex replacing
# the default), extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."

kind=${1:-address}
[ $# -ge 1 ] && shift
case $kind in
  address | thread | all) ;;
  *) echo "usage: $0 [address|thread|all] [ctest arguments...]" >&2; exit 2 ;;
esac
if [ "$kind" = all ]; then
  bash "$0" address "$@"
  exec bash "$0" thread "$@"
fi

bash scripts/install-deps.sh
JOBS=${JOBS:-$(bash scripts/cpu-count.sh)}
root=${BUILD_ROOT:-build}
start=$(date +%s)
stamp() { echo "sanitize.sh ($kind): $1 ($(( $(date +%s) - start )) s)"; }

# Timing-bound tests (scripts/real-time-tests.sh, the same list as under emulation).
real_speed=$(bash scripts/real-time-tests.sh)
# Whole-SLAM runs are 20-50x slower sanitized: the ones over LDSM_SANITIZE_MAX_NATIVE_SECONDS
# (default 5) in the native suite's last run (build/, when it has run) are left to the native
# suite; the shorter end-to-end runs (sim scenes, the real-data smoke tests) stay.
max_native=${LDSM_SANITIZE_MAX_NATIVE_SECONDS:-5}
slow=$(bash scripts/slow-tests.sh "$max_native" "${LDSM_NATIVE_BUILD_DIR:-build}")
if [ -z "$slow" ]; then
  # No native run to read: the runs over 5 s on the development machine.
  slow='LoopClosure\..*|SimOdometry\.(ForwardCorridorIsAccurate|LoopSceneFirstCornerTracks|RadialRefinementRepairsAWrongDistortion)|MapReuse\..*'
fi
echo "sanitize.sh: long whole-SLAM runs, not run: $slow"
real_speed+="|$slow"
# The installed-package test builds a consumer project with its own (unsanitized) flags against
# the sanitized static libraries: it cannot link, and it tests packaging, not memory.
real_speed+='|package\.find_package'
if [ "$kind" = address ]; then
  dir=${root}-asan
  flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1 -g1"
  # ThreadSanitizer's own test executables cannot link with AddressSanitizer.
  extra=(-DLDSM_TSAN_TESTS=OFF)
  labels=()
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  # python.leak measures python3's resident memory over 1000 submits: ASan's quarantine, shadow
  # memory and allocator caches make it grow by design (LeakSanitizer cannot run in the
  # uninstrumented interpreter, python/CMakeLists.txt); the native suite runs it.
  echo "sanitize.sh: python.leak (resident memory, grows under ASan by design), not run"
  real_speed+='|python\.leak'
else
  dir=${root}-tsan
  flags="-fsanitize=thread -O1 -g1"
  extra=(-DLDSM_TSAN_TESTS=OFF)
  # Where threads meet: the system (threaded mode, the mapping and loop-closing threads), the
  # live pipeline, the concurrency primitives and the pipeline stages.
  labels=(-L '^(system|live|pipeline|concurrency|capture|replay|loop)$')
  # scripts/tsan.supp: OpenCV's allocator seen across TBB threads (neither is instrumented).
  export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:exitcode=66:second_deadlock_stack=1:suppressions=$PWD/scripts/tsan.supp}
fi
exclude=${SANITIZE_EXCLUDE-^($real_speed)$}

cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="${flags%% -O1*}" \
  -DCMAKE_SHARED_LINKER_FLAGS="${flags%% -O1*}" \
  -DLDSM_BUILD_TESTS=ON -DLDSM_BUILD_BENCH=OFF -DLDSM_BUILD_APPS=ON -DLDSM_SIMD=auto \
  -DLDSM_NATIVE=OFF -DLDSM_WERROR=OFF "${extra[@]}" >/dev/null
cmake --build "$dir" -j "$JOBS"
stamp "built $dir"
args=(--test-dir "$dir" --output-on-failure --no-tests=error -j "$JOBS" --timeout 1800)
[ -n "$exclude" ] && { args+=(-E "$exclude"); echo "sanitize.sh: NOT RUN: $exclude"; }
ctest "${args[@]}" "${labels[@]}" "$@"
stamp "passed with no report"
