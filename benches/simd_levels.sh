#!/usr/bin/env bash
# Interleaved wall time of an old binary beside a new one run at its AVX2 and AVX-512 kernel
# builds (`raylab bench --simd`), on the same rows, cameras and thread count. Usage:
#   bash benches/simd_levels.sh OLD_BIN NEW_BIN [ROUNDS] [FRAMES] [THREADS]
# Each round runs every row in the three configurations, the order reversed every other
# round; prints per row each configuration's median frame time (a run's median, not its
# fastest frame: this VM's clock now and then gives one frame a fraction of its time), the
# median over the rounds, and the medians of each round's ratios (above 1: the second
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
    | sed -n 's/^median frame \([0-9.]*\) ms.*/\1/p'
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
# Times: the median over the rounds of each run's median frame. Ratios: the median over the
# rounds of each round's ratio (the three runs of a round are back to back, so a slow spell
# of the VM weighs on all three).
awk 'function median(list,   v, m, i, j, x) {m = split(list, v, " ")
       for (i = 2; i <= m; i++) {x = v[i]; for (j = i - 1; j >= 1 && v[j] > x; j--) v[j + 1] = v[j]; v[j + 1] = x}
       return m % 2 ? v[(m + 1) / 2] : (v[m / 2] + v[m / 2 + 1]) / 2}
     {k = $1 " " $2 " " $3; if (!(k in seen)) {seen[k] = 1; keys[++n] = k}
      c = k SUBSEP $4; t[c] = t[c] " " $5; r = ++count[c]; at[c SUBSEP r] = $5}
     END {for (i = 1; i <= n; i++) {k = keys[i]; split(k, p, " ")
       o = k SUBSEP "old"; a = k SUBSEP "avx2"; b = k SUBSEP "avx512"; ra = rb = rc = ""
       for (r = 1; r <= count[o]; r++) {
         ra = ra " " at[o SUBSEP r] / at[a SUBSEP r]; rb = rb " " at[a SUBSEP r] / at[b SUBSEP r]
         rc = rc " " at[o SUBSEP r] / at[b SUBSEP r]}
       printf "| %s | %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", p[1], p[2], p[3],
         median(t[o]), median(t[a]), median(t[b]), median(ra), median(rb), median(rc)}}' "$out"
