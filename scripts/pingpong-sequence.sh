#!/usr/bin/env bash
# Builds a long revisiting sequence from a TUM-Mono style folder (images/, times.txt, camera.txt,
# groundtruth.txt) or a KITTI odometry folder (sequences/NN/, poses/NN.txt, groundtruth.txt): the
# frames played forward, then backward, N times (symlinks, no copies), at the sequence's own frame
# interval, with the ground truth repeated to match. For map-reuse and soak runs (a robot
# patrolling the same place) and for drives the odometry has not been tuned on (backwards).
#   scripts/pingpong-sequence.sh SOURCE_DIR OUT_DIR [PASSES=5]
set -euo pipefail
src=$(cd "${1:?usage: pingpong-sequence.sh SOURCE_DIR OUT_DIR [PASSES]}" && pwd)
out=${2:?usage: pingpong-sequence.sh SOURCE_DIR OUT_DIR [PASSES]}
passes=${3:-5}

# The source frame (0..N-1) of each output frame, one per line: forward, backward, PASSES times,
# no frame repeated at the turning points.
play_order() {
  awk -v n="$1" -v passes="$2" 'BEGIN {
    for (p = 0; p < passes; ++p)
      for (d = 0; d < 2; ++d)
        for (i = 0; i < n; ++i) {
          if (i == 0 && (d == 1 || p > 0)) continue
          print d == 1 ? n - 1 - i : i
        }
  }'
}
# perl makes the links from "target<TAB>link" lines (an hour-long soak has over 100 000 frames: no
# process per frame).
make_links() {
  (cd "$1" && perl -ne 'chomp; my ($t, $l) = split /\t/; unlink $l; symlink($t, $l) or die "$l: $!\n"')
}

if [ -d "$src/sequences" ]; then
  # KITTI odometry layout (sequences/NN/image_0/*.png, times.txt, calib.txt; poses/NN.txt): the
  # timestamps renumbered at the sequence's own interval, the poses and groundtruth.txt repeated.
  # A car that reverses in an instant: every second leg is driven backwards.
  first_seq=("$src"/sequences/*)  # a glob, not `ls | head` (SIGPIPE under pipefail)
  seq=${first_seq[0]##*/}
  mkdir -p "$out/sequences/$seq/image_0" "$out/poses"
  cp "$src/sequences/$seq/calib.txt" "$out/sequences/$seq/"
  for f in camera.txt SOURCE.txt; do [ -f "$src/$f" ] && cp "$src/$f" "$out/"; done
  n=$(grep -c . "$src/sequences/$seq/times.txt")
  awk -v passes="$passes" -v src="$src" -v seq="$seq" -v out="$out" '
    FNR == 1 { file++ }
    file == 1 && !/^#/ && NF >= 8 { $1 = ""; gt[ngt++] = substr($0, 2); next }
    file == 2 && NF >= 1 { stamp[n++] = $1 + 0; next }
    file == 3 && NF >= 12 { pose[np++] = $0; next }
    file == 4 { order[m++] = $1 }
    END {
      dt = (stamp[n - 1] - stamp[0]) / (n - 1)
      print "# timestamp tx ty tz qx qy qz qw (camera-to-world), " passes \
        " forward+backward passes" > out "/groundtruth.txt"
      for (k = 0; k < m; ++k) {
        j = order[k]
        printf "%e\n", k * dt > out "/sequences/" seq "/times.txt"
        if (j < ngt) print sprintf("%.6f", k * dt) " " gt[j] >> out "/groundtruth.txt"
        if (j < np) print pose[j] > out "/poses/" seq ".txt"
        printf "%s/sequences/%s/image_0/%06d.png\t%06d.png\n", src, seq, j, k
      }
    }' "$src/groundtruth.txt" "$src/sequences/$seq/times.txt" "$src/poses/$seq.txt" \
    <(play_order "$n" "$passes") | make_links "$out/sequences/$seq/image_0"
  k=$(grep -c . "$out/sequences/$seq/times.txt")
  echo "pingpong-sequence.sh: $k frames ($passes forward+backward passes, KITTI layout) in $out"
  exit 0
fi

mkdir -p "$out/images"
cp "$src/camera.txt" "$out/"
[ -f "$src/pcalib.txt" ] && cp "$src/pcalib.txt" "$out/"
[ -f "$src/vignette.png" ] && cp "$src/vignette.png" "$out/"
mapfile -t frames < <(awk '!/^#/ && NF >= 2 {print $1}' "$src/times.txt")
mapfile -t stamps < <(awk '!/^#/ && NF >= 2 {print $2}' "$src/times.txt")
n=${#frames[@]}
dt=$(awk -v a="${stamps[0]}" -v b="${stamps[$((n - 1))]}" -v n="$n" 'BEGIN {printf "%.9f", (b - a) / (n - 1)}')
first_image=("$src"/images/*)  # a glob, not `ls | head` (SIGPIPE under pipefail)
ext=${first_image[0]##*.}
: > "$out/times.txt"
gt_out="$out/groundtruth.txt"
echo "# timestamp tx ty tz qx qy qz qw (camera-to-world), $passes forward+backward passes" > "$gt_out"
# One awk pass writes times.txt, the ground truth (by source timestamp) and the list of links.
awk -v dt="$dt" -v ext="$ext" -v src="$src/images" -v times="$out/times.txt" -v gt_out="$gt_out" '
  BEGIN { n = 0 }
  FNR == 1 { file++ }
  file == 1 && !/^#/ && NF >= 8 { key = $1; $1 = ""; gt[key] = substr($0, 2); next }
  file == 2 && !/^#/ && NF >= 2 { frame[n] = $1; stamp[n] = $2; n++; next }
  file == 3 { order[m++] = $1 }
  END {
    for (k = 0; k < m; ++k) {
      j = order[k]
      name = sprintf("%06d", k)
      t = sprintf("%.6f", k * dt)
      print name " " t > times
      key = sprintf("%.6f", stamp[j])
      if (key in gt) print t " " gt[key] >> gt_out
      print src "/" frame[j] "." ext "\t" name "." ext
    }
  }' "$src/groundtruth.txt" "$src/times.txt" <(play_order "$n" "$passes") |
  make_links "$out/images"
k=$(grep -c . "$out/times.txt")
echo "pingpong-sequence.sh: $k frames ($passes passes of $n) in $out"
