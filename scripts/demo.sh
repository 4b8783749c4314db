#!/usr/bin/env bash
# The README's main job: installs what is needed (apt), builds ldsm, renders the built-in
# synthetic loop scene, runs SLAM on it and prints the accuracy against the scene's ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out/demo}
bash scripts/configure.sh "$BUILD_DIR"
cmake --build "$BUILD_DIR" -j "$(bash scripts/cpu-count.sh)" --target ldsm
LDSM="$BUILD_DIR/apps/ldsm"
echo "== rendering the synthetic loop scene into $OUT/scene"
"$LDSM" sim --scene "${SCENE:-loop}" --out "$OUT/scene"
echo "== running SLAM"
"$LDSM" run --dataset "$OUT/scene" --out "$OUT/result" --deterministic
echo "== evaluating"
"$LDSM" eval --gt "$OUT/scene/groundtruth.txt" --est "$OUT/result/trajectory.txt" \
        --plot "$OUT/result/trajectory.png" --json "$OUT/result/eval.json"
echo "outputs: $OUT/result (trajectory.txt, keyframes.txt, points.ply, stats.json, trajectory.png)"
