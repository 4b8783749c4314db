#!/usr/bin/env bash
# Cuts frames FIRST..LAST (inclusive, by frame id) out of a TUM-Mono style folder (images/,
# times.txt, camera.txt, groundtruth.txt; pcalib.txt and vignette.png when present): symlinks to
# the images, times.txt and the ground truth cut alike. For map sessions: run one part with
# --save-map, another with --load-map (docs/map-sessions.md).
#   scripts/split-sequence.sh SOURCE_DIR OUT_DIR FIRST LAST
set -euo pipefail
usage="usage: split-sequence.sh SOURCE_DIR OUT_DIR FIRST LAST"
src=$(cd "${1:?$usage}" && pwd)
out=${2:?$usage}
first=${3:?$usage}
last=${4:?$usage}
rm -rf "$out"
mkdir -p "$out/images"
cp "$src/camera.txt" "$out/"
for f in pcalib.txt vignette.png; do [ -f "$src/$f" ] && cp "$src/$f" "$out/"; done
awk -v a="$first" -v b="$last" '!/^#/ && NF >= 2 && $1 + 0 >= a && $1 + 0 <= b' \
  "$src/times.txt" > "$out/times.txt"
# The first image's extension (a glob, not `ls | head`: under pipefail, ls killed by SIGPIPE
# when head has read its line fails the script, now and then).
first_image=("$src"/images/*)
ext=${first_image[0]##*.}
awk -v src="$src/images" -v ext="$ext" '{print src "/" $1 "." ext "\t" $1 "." ext}' "$out/times.txt" |
  (cd "$out/images" && perl -ne 'chomp; my ($t, $l) = split /\t/; symlink($t, $l) or die "$l: $!\n"')
if [ -f "$src/groundtruth.txt" ]; then
  awk 'NR == FNR { keep[$2] = 1; next } /^#/ || ($1 in keep)' "$out/times.txt" \
    "$src/groundtruth.txt" > "$out/groundtruth.txt"
fi
echo "split-sequence.sh: $(grep -c . "$out/times.txt") frames ($first-$last) in $out"
