#!/usr/bin/env bash
# Interleaved wall time of an old binary beside a new one run at its AVX2 and AVX-512 kernel
# builds (`raylab bench --simd`), on the same rows, cameras and thread count: session 23's
# table. Usage:
#   bash benches/simd_levels.sh OLD_BIN NEW_BIN [ROUNDS] [FRAMES] [THREADS]
# Each round runs every row in the three configurations, the order reversed every other
# round; prints per row the minimum frame time of each and their ratios (above 1: the second
# faster). The new binary's CPU must have AVX-512. Rows: the Cornell box, and with
# ../shared/scenes (SHARED=... for another place) the bunny, Igea, the 1M mesh where
# target/igea_1m.obj exists, and the field of 1,000 bunnies (FIELD_ROUNDS rounds of 3 frames).
set -euo pipefail
old=$1 new=$2 rounds=${3:-5} frames=${4:-20} threads=${5:-1}
shared=${SHARED:-../shared/scenes}
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores, $threads thread(s)"
rows=("cornell flat 1280x720" "cornell shadows 1280x720")
if [ -d "$shared" ]; then
  for s in "bunny flat 320x180" "bunny flat 640x360" "bunny flat 1280x720" "igea flat 320x180" "igea flat 640x360" "igea flat 1280x720"; do
    set -- $s; rows+=("$shared/$1.obj $2 $3")
  done
  [ -f target/igea_1m.obj ] && rows+=("target/igea_1m.obj flat 640x360")
fi
field_rows=()
[ -d "$shared" ] && field_rows=("benches/scenes/bunny_field.scene flat 320x180" "benches/scenes/bunny_field.scene flat 1280x720")
ms() { # bin simd-flag scene step size frames
  "$1" bench $2 --scene "$3" --step "$4" --width "${5%x*}" --height "${5#*x}" --threads "$threads" --frames "$6" \
    | sed -n 's/^median frame [0-9.]* ms (min \([0-9.]*\),.*/\1/p'
}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
measure() { # rounds frames rows...
  local n=$1 f=$2; shift 2
  for row in "$@"; do
    set -- $row
    for ((r = 1; r <= n; r++)); do
      order="old avx2 avx512"; (( r % 2 )) || order="avx512 avx2 old"
      for c in $order; do
        case $c in
          old) t=$(ms "$old" "" "$1" "$2" "$3" "$f") ;;
          *) t=$(ms "$new" "--simd $c" "$1" "$2" "$3" "$f") ;;
        esac
        echo "$(basename "$1") $2 $3 $c $t" >>"$out"
      done
    done
  done
}
measure "$rounds" "$frames" "${rows[@]}"
[ ${#field_rows[@]} -gt 0 ] && measure "${FIELD_ROUNDS:-3}" 3 "${field_rows[@]}"
echo "| scene | step | size | old ms | new, AVX2 build ms | new, AVX-512 build ms | new AVX2 ÷ old | AVX-512 ÷ AVX2 | new AVX-512 ÷ old |"
echo "|---|---|---|---|---|---|---|---|---|"
awk '{k = $1 " " $2 " " $3; if (!(k in seen)) {seen[k] = 1; keys[++n] = k}
      c = k SUBSEP $4; if (!(c in best) || $5 < best[c]) best[c] = $5}
     END {for (i = 1; i <= n; i++) {k = keys[i]; split(k, p, " ")
       o = best[k SUBSEP "old"]; a = best[k SUBSEP "avx2"]; b = best[k SUBSEP "avx512"]
       printf "| %s | %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", p[1], p[2], p[3], o, a, b, o / a, a / b, o / b}}' "$out"
