#!/usr/bin/env bash
# Deterministic trajectory checksums, for behaviour-preserving refactors: runs `ldsm run
# --deterministic` on the synthetic scenes and on the real sequences in ../shared/data (when
# present), with and without loop closure, and prints one line per run:
#   <md5 of trajectory.txt>  <run name>
# Usage: scripts/trajectory-checksums.sh [BUILD_DIR] > checksums.txt ; diff against an earlier list.
# LDSM_RUN_ARGS adds arguments to every run, e.g. LDSM_RUN_ARGS="--config threads.yaml" with
# system.parallel_threads: 2 (the lists must then be identical to the one-thread lists).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
LDSM="$BUILD_DIR/apps/ldsm"
DATA=${LDSM_DATA:-../shared/data}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
runs=()
for scene in loop forward rotation short; do
  "$LDSM" sim --scene "$scene" --out "$WORK/sim_$scene" >/dev/null 2>&1
  runs+=("sim:$scene=$WORK/sim_$scene")
done
for seq in kitti00_200 vamr_desk_loop; do
  [ -d "$DATA/$seq" ] && runs+=("$seq=$DATA/$seq")
done
for r in "${runs[@]}"; do
  name=${r%%=*}
  path=${r#*=}
  for mode in loop no-loop; do
    flag=""
    [ "$mode" = no-loop ] && flag=--no-loop
    out="$WORK/out"
    rm -rf "$out"
    "$LDSM" run --dataset "$path" --out "$out" --deterministic --no-eval $flag ${LDSM_RUN_ARGS:-} >/dev/null 2>&1
    echo "$(md5sum < "$out/trajectory.txt" | cut -d' ' -f1)  $name ($mode)"
  done
done
