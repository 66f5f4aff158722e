#!/usr/bin/env bash
# Instruction counts of two raylab binaries on the same rows (callgrind, 1 thread, a warm-up and
# 2 frames, counted inside `render_into_cancellable` only), as a markdown table. Usage:
#   bash benches/instructions.sh OLD_BIN NEW_BIN
# Needs valgrind; run from the repository's root. The mesh rows need ../shared/scenes (SHARED=...
# for another place), the 1M-triangle row target/igea_1m.obj.
set -euo pipefail
old=$1 new=$2
shared=${SHARED:-../shared/scenes}
rows=("cornell flat 1280 720" "cornell shadows 1280 720" "cornell flat 640 360" "cornell shadows 640 360")
if [ -d "$shared" ]; then
  rows+=("$shared/bunny.obj flat 640 360" "$shared/bunny.obj shadows 640 360" "$shared/igea.obj flat 640 360"
         "$shared/bunny.obj flat 320 180" "$shared/bunny.obj flat 1280 720" "$shared/bunny.obj shadows 1280 720"
         "benches/scenes/bunny_field.scene flat 320 180")
fi
# The 1M-triangle mesh where it was made (docs/performance.md: cargo run --release --example subdivide).
[ -f target/igea_1m.obj ] && rows+=("target/igea_1m.obj flat 640 360")
rows+=("assets/scenes/ball_field.scene shadows 320 180")
out=$(mktemp)
trap 'rm -f "$out"' EXIT
count() {
  valgrind --tool=callgrind --callgrind-out-file="$out" --toggle-collect='*render_into_cancellable*' \
    "$1" bench --scene "$2" --step "$3" --width "$4" --height "$5" --threads 1 --frames 2 >/dev/null 2>&1
  callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}'
}
echo "| scene | step | size | old | new | change |"
echo "|---|---|---|---|---|---|"
for row in "${rows[@]}"; do
  set -- $row
  a=$(count "$old" "$@") b=$(count "$new" "$@")
  awk -v s="$(basename "$1" .obj)" -v st="$2" -v w="$3" -v h="$4" -v a="$a" -v b="$b" \
    'BEGIN {printf "| %s | %s | %s×%s | %.1fM | %.1fM | %+.1f%% |\n", s, st, w, h, a/1e6, b/1e6, (b/a-1)*100}'
done
