#!/usr/bin/env bash
# Instructions per frame of the odometry (deterministic, one thread, loop closure off) on the
# first frames of the real sequences, counted by valgrind's callgrind: stable on loaded machines
# where wall time is not. Image decoding, start-up and initialisation are included, as in the
# wall time bench_sequences prints. Prints "NAME INSTRUCTIONS_PER_FRAME" lines, the format of
# bench_sequences --instructions FILE.
# Usage: scripts/instructions-per-frame.sh [BUILD_DIR] [DATA_DIR] [FRAMES] > FILE
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
DATA_DIR=${2:-../shared/data}
FRAMES=${3:-60}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for name in kitti00_200 vamr_desk_loop; do
  [ -d "$DATA_DIR/$name" ] || continue
  valgrind --tool=callgrind --callgrind-out-file="$tmp/$name.out" \
    "$BUILD_DIR/apps/ldsm" run --dataset "$DATA_DIR/$name" --deterministic --no-loop \
    --max-frames "$FRAMES" --flush-every 0 --no-eval --out "$tmp/$name" >/dev/null 2>"$tmp/$name.log"
  total=$(sed -n 's/^summary: *\([0-9]*\).*/\1/p' "$tmp/$name.out")
  echo "$name $((total / FRAMES))"
done
