#!/usr/bin/env bash
# Interleaved speed comparison of two raylab binaries on the same scenes, cameras and thread
# counts (the "same speed" check of a refactor). Usage:
#   bash benches/before_after.sh OLD_BIN NEW_BIN [ROUNDS] [FRAMES]
# (SIZE=640x360 for another frame size than 1280x720; ROWS, below, for other scenes.)
# Each round runs every row with both binaries, alternating which goes first; prints the median
# frame time of each run and, per row, the median over rounds of new/old.
set -euo pipefail
old=$1 new=$2 rounds=${3:-3} frames=${4:-7}
shared=${SHARED:-../shared/scenes}
size=${SIZE:-1280x720}
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores; $($new bench --frames 1 --width 8 --height 8 | sed -n "s/.*\(simd: .*\)/\1/p")"
rows=("cornell flat" "cornell shadows" "assets/scenes/cornell_spheres.scene flat" "assets/scenes/cornell_spheres.scene shadows")
if [ -d "$shared" ]; then
  rows+=("$shared/bunny.obj flat" "$shared/bunny.obj shadows" "$shared/igea.obj flat" "$shared/igea.obj shadows")
fi
# ROWS="scene step;scene step;..." times those rows instead.
if [ -n "${ROWS:-}" ]; then IFS=';' read -r -a rows <<<"$ROWS"; fi
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
ms() { "$1" bench --scene "$2" --step "$3" --width "${size%x*}" --height "${size#*x}" --threads 2 --frames "$frames" \
         | sed -n 's/^median frame \([0-9.]*\) ms.*/\1/p'; }
declare -A ratios
for ((r = 1; r <= rounds; r++)); do
  for row in "${rows[@]}"; do
    set -- $row
    if (( r % 2 )); then a=$(ms "$old" "$1" "$2"); b=$(ms "$new" "$1" "$2");
    else b=$(ms "$new" "$1" "$2"); a=$(ms "$old" "$1" "$2"); fi
    ratio=$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.3f", b / a}')
    ratios[$row]+="$ratio "
    echo "round $r: $(basename "$1") $2: old $a ms, new $b ms, new/old $ratio"
  done
done
echo
echo "| scene | step | new/old per round | median |"
echo "|---|---|---|---|"
for row in "${rows[@]}"; do
  set -- $row
  m=$(tr ' ' '\n' <<<"${ratios[$row]}" | grep . | median)
  echo "| $(basename "$1") | $2 | ${ratios[$row]}| $m |"
done
