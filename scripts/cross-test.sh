#!/usr/bin/env bash
# Cross-builds ldsm for an ARM target and runs its tests under qemu-user, from a fresh Debian 12
# x86-64 machine (root or sudo):
#
#   bash scripts/cross-test.sh aarch64     # everything: libraries, loop closure, ldsm tool, all tests
#   bash scripts/cross-test.sh armhf       # ARMv7 + NEON: everything built, the unit tests run
#
# Steps: installs the host packages and makes the target sysroot (toolchains/prepare-sysroot.sh,
# cached in ${LDSM_CROSS_CACHE:-$HOME/.cache/ldsm-cross}/<arch>), configures with
# toolchains/<triplet>.cmake into build-<arch>, builds, runs ctest (every test executable runs
# under qemu-<arch>-static; see docs/arm.md).
#
# Environment: BUILD_DIR (default build-<arch>), JOBS (default: scripts/cpu-count.sh), NICE
# (default 0: niceness of the build and tests), LDSM_CROSS_BENCH=1 also builds the benchmarks,
# LDSM_CROSS_SKIP_LABELS (a ctest -LE regex of test labels, i.e. tests/ folders, not to run;
# armhf default: see below),
# LDSM_CROSS_EXCLUDE (a ctest -E regex of tests not to run; default: the known ARM failures below).
# Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."

[ $# -ge 1 ] || { echo "usage: $0 aarch64|armhf [ctest arguments...]" >&2; exit 2; }
arch=$1
shift
case $arch in
  aarch64 | arm64) arch=aarch64 toolchain=toolchains/aarch64-linux-gnu.cmake
    default_skip="" ;;
  armhf | armv7) arch=armhf toolchain=toolchains/arm-linux-gnueabihf.cmake
    # Under qemu-arm: the unit tests (every tests/unit folder) and the package test; the system
    # tests (whole SLAM runs, label "system") are left to aarch64, which runs the same kernels.
    default_skip="^system$" ;;
  *) echo "usage: $0 aarch64|armhf [ctest arguments...]" >&2; exit 2 ;;
esac

# Not run under emulation, on every ARM target (see docs/arm.md):
#  * The real-time tests of scripts/real-time-tests.sh (RealtimeReplay.{OneTimesRealTime,
#    FasterThanRealTime}..., LiveRelocalisation.*, RunLiveCli.RealtimeReplayReports... and the two
#    RunFaults tests that signal a real-time replay once it tracks; sanitize.sh leaves out the
#    same): real-time replay needs the machine's real speed (qemu is ~10x slower: most frames are
#    dropped, as they should be, and a 2-second clip never initialises). They run natively on a
#    board.
#  * Long whole-SLAM and real-data runs (LoopClosure.*, the other SimOdometry runs, the EuRoC
#    standing-still initialiser tests, the allocation run over a whole sequence, ...): 15-95 s
#    natively, 3-35 minutes each under qemu (the drifting-loop test hit ctest's 30-minute limit on
#    CI). They would push the CI job past its time limit and test nothing ARM-specific that
#    SimOdometry.ForwardCorridorIsAccurate (the end-to-end run kept under qemu), the SIMD agreement
#    tests and the PoseGraph tests do not; they run in the native suite.
known_arm_failures=$(bash scripts/real-time-tests.sh)
too_slow_under_emulation='LoopClosure\..*|SimOdometry\.(LoopSceneFirstCornerTracks|DeterministicModeIsBitIdentical|ThreadedModeTracksLikeDeterministic|RadialRefinementRepairsAWrongDistortion)|Initializer(Hypotheses|Refusal)\.EurocDroneStandingStillNeverInitialises|SystemAllocation\.TrackingNonKeyframesAllocatesNothingInSteadyState|RunCommand\.UnreadableFrameMidSequenceKeepsTheTrajectorySoFar|SystemPipeline\.LatestPoseIsTheLastTrackedPoseInBothModes'
# Map reuse's two-lap and noise runs (107 s and 29 s natively; the two-lap run hit the 30-minute
# limit under qemu on CI) join them; MapReuse.ForwardCorridorReactivatesNothing (8 s) stays.
too_slow_under_emulation+='|MapReuse\.(SecondLapOfALoopIsTrackedAgainstTheMapAndHardlyGrowsIt|AfterNoiseTrackingResumesInTheOldMapFrame)'
# And any test that took longer than LDSM_CROSS_MAX_NATIVE_SECONDS (default 20) in the native
# suite's last run (its CTestCostData.txt, when the native build folder has one: CI runs the native
# suite first), so that a new long test cannot push this job past ctest's limit unnoticed.
max_native=${LDSM_CROSS_MAX_NATIVE_SECONDS:-20}
slow_native=$(bash scripts/slow-tests.sh "$max_native" "${LDSM_NATIVE_BUILD_DIR:-build}")
if [ -n "$slow_native" ]; then
  echo "cross-test.sh: over ${max_native} s in the native suite's last run, not run: $slow_native"
  too_slow_under_emulation+="|$slow_native"
fi
exclude=${LDSM_CROSS_EXCLUDE-^($known_arm_failures|$too_slow_under_emulation)$}

BUILD_DIR=${BUILD_DIR:-build-$arch}
JOBS=${JOBS:-$(bash scripts/cpu-count.sh)}
NICE=${NICE:-0}
skip_labels=${LDSM_CROSS_SKIP_LABELS-$default_skip}
bench=OFF
[ "${LDSM_CROSS_BENCH:-0}" = 1 ] && bench=ON

start=$(date +%s)
stamp() { echo "cross-test.sh: $1 ($(( $(date +%s) - start )) s)"; }

sysroot=$(bash toolchains/prepare-sysroot.sh "$arch" | tail -n 1)
stamp "sysroot $sysroot ready"

# No Python module: its tests run the host's python3, which cannot load an ARM module (build it on
# the board with the target's python3-dev and pybind11-dev). The viewer is built and tested.
nice -n "$NICE" cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_TOOLCHAIN_FILE="$PWD/$toolchain" -DLDSM_SYSROOT="$sysroot" -DLDSM_WERROR=ON \
  -DLDSM_BUILD_BENCH="$bench" -DLDSM_BUILD_PYTHON=OFF
nice -n "$NICE" cmake --build "$BUILD_DIR" -j "$JOBS"
stamp "built $BUILD_DIR"

ctest_args=(--test-dir "$BUILD_DIR" --output-on-failure --no-tests=error -j "$JOBS" --timeout 1800)
[ -n "$skip_labels" ] && ctest_args+=(-LE "$skip_labels")
if [ -n "$exclude" ]; then
  ctest_args+=(-E "$exclude")
  echo "cross-test.sh: NOT RUN under emulation (LDSM_CROSS_EXCLUDE): $exclude"
fi
nice -n "$NICE" ctest "${ctest_args[@]}" "$@"
stamp "ctest passed under qemu ($arch)"
