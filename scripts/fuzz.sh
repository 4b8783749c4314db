#!/usr/bin/env bash
# Fuzzes every parser of outside input with libFuzzer (docs/reliability.md, "Fuzzing"):
#
#   bash scripts/fuzz.sh [SECONDS]        # each target for SECONDS (default 60)
#   FUZZ_RUNS=1000000 bash scripts/fuzz.sh   # each target for that many executions instead
#   FUZZ_TARGETS="camera_txt pcalib" bash scripts/fuzz.sh 30   # some targets only
#
# Builds the targets of tests/fuzz with Debian's clang into build-fuzz (everything instrumented:
# -fsanitize=fuzzer-no-link,address,undefined), then runs each on its seed corpus
# (tests/fuzz/corpus/<target>, read only) and a working corpus (build-fuzz/corpus/<target>, kept
# between runs). A crash, a sanitizer report, a leak, an exception other than ldsm::Error, a hang
# (over 10 s on one input) or an input needing over 2 GB stops that target and fails the script;
# the input is saved as build-fuzz/artifacts/<target>/crash-... (add it to the seed corpus once
# fixed: the test suite replays every corpus file). Prints executions and time per target.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
targets=${FUZZ_TARGETS:-camera_txt kalibr_yaml kitti_calib pcalib vignette image_decode timestamps trajectory config_yaml vocabulary map_file}
dir=${BUILD_DIR:-build-fuzz}
JOBS=${JOBS:-$(bash scripts/cpu-count.sh)}

bash scripts/install-deps.sh
if ! command -v clang++ >/dev/null 2>&1 || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "fuzz.sh: installing clang and its libFuzzer runtime (clang, libclang-rt-14-dev)"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev
fi

flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1 -g1"
CC=clang CXX=clang++ cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DLDSM_FUZZ=ON -DLDSM_BUILD_TESTS=ON -DLDSM_BUILD_BENCH=OFF -DLDSM_BUILD_APPS=OFF \
  -DLDSM_TSAN_TESTS=OFF -DLDSM_WERROR=OFF -DLDSM_WITH_LIBCAMERA=OFF >/dev/null
build_targets=()
for t in $targets; do build_targets+=("fuzz_$t"); done
cmake --build "$dir" -j "$JOBS" --target "${build_targets[@]}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
if [ -n "${FUZZ_RUNS:-}" ]; then limit=(-runs="$FUZZ_RUNS"); else limit=(-max_total_time="$seconds"); fi
summary=()
failed=0
for t in $targets; do
  mkdir -p "$dir/corpus/$t" "$dir/artifacts/$t"
  log="$dir/fuzz_$t.log"
  start=$(date +%s)
  rc=0
  "$dir/tests/fuzz/fuzz_$t" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$dir/artifacts/$t/" "$dir/corpus/$t" "tests/fuzz/corpus/$t" >"$log" 2>&1 || rc=$?
  secs=$(($(date +%s) - start))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  if [ "$rc" != 0 ]; then
    failed=1
    summary+=("$(printf '%-14s FAILED after %s s (%s executions): see %s' "$t" "$secs" "${execs:-?}" "$log")")
  else
    summary+=("$(printf '%-14s %12s executions in %5s s, corpus %s files' "$t" "${execs:-?}" "$secs" \
      "$(find "$dir/corpus/$t" -type f | wc -l)")")
  fi
done
echo "fuzz.sh: results (clang $(clang++ -dumpversion))"
printf '  %s\n' "${summary[@]}"
exit "$failed"
