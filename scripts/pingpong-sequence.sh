#!/usr/bin/env bash
# Builds a long revisiting sequence from a TUM-Mono style folder (images/, times.txt, camera.txt,
# groundtruth.txt): the frames played forward, then backward, N times (symlinks, no copies), at the
# sequence's own frame interval, with the ground truth repeated to match. For map-reuse and soak
# runs: a robot patrolling the same place.
#   scripts/pingpong-sequence.sh SOURCE_DIR OUT_DIR [PASSES=5]
set -euo pipefail
src=$(cd "${1:?usage: pingpong-sequence.sh SOURCE_DIR OUT_DIR [PASSES]}" && pwd)
out=${2:?usage: pingpong-sequence.sh SOURCE_DIR OUT_DIR [PASSES]}
passes=${3:-5}
mkdir -p "$out/images"
cp "$src/camera.txt" "$out/"
[ -f "$src/pcalib.txt" ] && cp "$src/pcalib.txt" "$out/"
[ -f "$src/vignette.png" ] && cp "$src/vignette.png" "$out/"
mapfile -t frames < <(awk '!/^#/ && NF >= 2 {print $1}' "$src/times.txt")
mapfile -t stamps < <(awk '!/^#/ && NF >= 2 {print $2}' "$src/times.txt")
n=${#frames[@]}
dt=$(awk -v a="${stamps[0]}" -v b="${stamps[$((n - 1))]}" -v n="$n" 'BEGIN {printf "%.9f", (b - a) / (n - 1)}')
ext=$(ls "$src/images" | head -n 1 | sed 's/.*\.//')
: > "$out/times.txt"
gt_out="$out/groundtruth.txt"
echo "# timestamp tx ty tz qx qy qz qw (camera-to-world), $passes forward+backward passes" > "$gt_out"
# ground truth by source timestamp
declare -A gt
while read -r t rest; do gt[$t]=$rest; done < <(awk '!/^#/ && NF >= 8' "$src/groundtruth.txt")
k=0
for ((p = 0; p < passes; ++p)); do
  for dir in fwd bwd; do
    for ((i = 0; i < n; ++i)); do
      j=$i
      [ "$dir" = bwd ] && j=$((n - 1 - i))
      # no repeated frame at the turning points
      { [ "$dir" = bwd ] && [ "$i" -eq 0 ]; } && continue
      { [ "$dir" = fwd ] && [ "$p" -gt 0 ] && [ "$i" -eq 0 ]; } && continue
      name=$(printf "%06d" "$k")
      ln -sf "$src/images/${frames[$j]}.$ext" "$out/images/$name.$ext"
      t=$(awk -v k="$k" -v dt="$dt" 'BEGIN {printf "%.6f", k * dt}')
      echo "$name $t" >> "$out/times.txt"
      key=$(printf "%.6f" "${stamps[$j]}")
      [ -n "${gt[$key]:-}" ] && echo "$t ${gt[$key]}" >> "$gt_out"
      k=$((k + 1))
    done
  done
done
echo "pingpong-sequence.sh: $k frames ($passes passes of $n) in $out"
