#!/usr/bin/env bash
# raylab alone on every scene (docs/performance.md): builds the release binary and runs
# `raylab bench` for each row, printing Markdown rows.
# Usage: bash benches/readme_table.sh [FRAMES]   (needs ../shared/scenes for the mesh rows)
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-7}
cargo build --release -q --bin raylab --example subdivide
bin=target/release/raylab
shared=../shared/scenes
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores, $(date -u +%F)"
echo
echo "| scene | size | step | method | accel | threads | build ms | median frame ms | Mrays/s |"
echo "|---|---|---|---|---|---|---|---|---|"
row() { # scene step method threads extra...
  local scene=$1 step=$2 method=$3 threads=$4; shift 4
  local out
  out=$($bin bench --scene "$scene" --width 1280 --height 720 --step "$step" --method "$method" \
        --threads "$threads" --frames "$frames" "$@")
  local accel build median mrays
  accel=$(sed -n 's/.*accel: \([a-z]*\), build \([0-9.]*\) ms.*/\1/p' <<<"$out")
  build=$(sed -n 's/.*accel: [a-z]*, build \([0-9.]*\) ms.*/\1/p' <<<"$out")
  median=$(sed -n 's/^median frame \([0-9.]*\) ms.*/\1/p' <<<"$out")
  mrays=$(sed -n 's/^mrays_per_s=//p' <<<"$out")
  local extra=""; [ $# -gt 0 ] && extra=" ($*)"
  echo "| $(basename "$scene") | 1280x720 | $step | $method$extra | $accel | $threads | $build | $median | $mrays |"
}
for t in 1 2; do
  for m in adaptive watertight; do
    row cornell flat $m $t
    row cornell shadows $m $t
  done
done
row cornell flat adaptive 2 --no-tile-culling
row cornell flat moller 2
row cornell flat cramer 2
if [ -d "$shared" ]; then
  for t in 1 2; do
    for m in adaptive watertight; do
      row "$shared/bunny.obj" flat $m $t
      row "$shared/igea.obj" flat $m $t
    done
  done
  row "$shared/bunny.obj" shadows adaptive 2
  # The 1M-triangle mesh: igea subdivided 1:4 (SOURCES.md), made once under target/.
  [ -f target/igea_1m.obj ] || target/release/examples/subdivide "$shared/igea.obj" target/igea_1m.obj >/dev/null
  for t in 1 2; do row target/igea_1m.obj flat adaptive $t; done
fi
