#!/usr/bin/env bash
# The scene files' rows (docs/performance.md): raylab bench on the example scenes, 2 threads, median of
# FRAMES frames after a warm-up, with the whole run's wall time and peak memory (GNU time).
# Usage: bash benches/scene_rows.sh [BIN] [FRAMES]   (the bunny field needs ../shared)
set -euo pipefail
bin=${1:-target/release/raylab} frames=${2:-7}
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores; $($bin bench --frames 1 --width 8 --height 8 | sed -n "s/.*\(simd: .*\)/\1/p")"
scenes=(cornell assets/scenes/cornell_spheres.scene assets/scenes/transform_stack.scene assets/scenes/ball_field.scene)
[ -f ../shared/scenes/bunny.obj ] && scenes+=(benches/scenes/bunny_field.scene)
echo "| scene | primitives | size | step | build ms | median frame ms | frames/s | Mrays/s | run s | peak MB |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  for size in 1280x720 640x360; do
    for step in flat shadows; do
      out=$( { /usr/bin/time -f "TIME %e %M" "$bin" bench --scene "$scene" --width "${size%x*}" --height "${size#*x}" \
                 --step "$step" --threads 2 --frames "$frames"; } 2>&1 )
      prims=$(sed -n 's/.*(\([0-9]*\) primitives.*/\1/p' <<<"$out" | head -1)
      build=$(sed -n 's/.*build \([0-9.]*\) ms.*/\1/p' <<<"$out" | head -1)
      ms=$(sed -n 's/^median frame \([0-9.]*\) ms.*/\1/p' <<<"$out")
      mr=$(sed -n 's/^mrays_per_s=//p' <<<"$out")
      read -r _ wall kb <<<"$(grep '^TIME' <<<"$out")"
      fps=$(awk -v m="$ms" 'BEGIN {printf "%.1f", 1000 / m}')
      echo "| $(basename "$scene") | $prims | $size | $step | $build | $ms | $fps | $mr | $wall | $((kb / 1024)) |"
    done
  done
done
