#!/usr/bin/env bash
# The benchmark set: the built-in scene, the procedural interiors and a public
# glTF model from Debian's assimp-testmodels, each seen from a viewer standing
# in it. Per scene, `fovea render --mode both` on the FOVE eye (1280x1440, full
# and foveated frames interleaved, medians of FRAMES, of 4 x FRAMES for the
# cheap public model) gives the speedup, what
# the content allows (content_speedup), the trace's own speedup, the fixed
# cost, and the cost per ray; a 320x360 full render is its picture.
# Writes DIR/scenes.md (headed by the commands and this machine), DIR/json/<scene>.json
# and DIR/img/<scene>.png.
# FRAMES 45: on a shared machine the median of 15 frame pairs can follow one
# slow spell of it; 45 make that rarer (not impossible: a run's ratios are
# worth repeating before reading a hundredth into them).
# Usage: bench/scenes.sh [DIR [FRAMES]]   (default: out/scenes 45); needs a built tree (scripts/run.sh or bench.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
dir=${1:-out/scenes}
frames=${2:-45}
fovea=build/bin/fovea
results_need bench/scenes.sh "$fovea"
mkdir -p "$dir/img" "$dir/json" out/cache
engine_glb=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
# name | --scene | viewer options | frames per FRAMES: a scene whose frames
# cost a tenth of the others' runs more of them, so that its medians span a
# few seconds of this machine too rather than one slow spell of it
scenes=(
  "default|default||1"
  "room|room||1"
  "hall|hall||1"
  "dense|dense||1"
  "engine|$engine_glb|--pose 450,300,420 --look-at 0,-80,100|4"
)
common=(--preset fove --mode both --interpolation msm --k 5 --cache-dir out/cache --json)
{
  echo "# Benchmark set: speedup against what the content allows"
  echo
  results_machine
  echo "Command per scene: \`$fovea render --scene SCENE VIEWER --frames N ${common[*]}\` (bench/scenes.sh)."
  echo "Full and foveated frames interleaved in one run; times are medians of N frames (its column), speedups medians of the frame pairs' ratios (the first pair left out)."
  echo "Trace = selection + rays + engine callback; fixed = reconstruction + temporal history."
  echo "ns per ray = trace time x threads / rays traced (primary + shadow + reflection + refraction)."
  echo "Pays above: the full-frame time below which the foveated frame is slower (fixed x s / (s - 1), s the trace speedup)."
  echo
  echo "| scene | triangles | effects | viewer | frames | full ms | foveated ms | speedup | content allows | trace speedup | trace / content | fixed ms | pays above, full ms | ns per ray, full | ns per ray, foveated |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$dir/scenes.md"
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene viewer factor <<< "$entry"
  n=$((frames * factor))
  # shellcheck disable=SC2086  # the viewer options split into words
  "$fovea" render --scene "$scene" $viewer --frames "$n" "${common[@]}" > "$dir/json/$name.json"
  # shellcheck disable=SC2086
  "$fovea" render --scene "$scene" $viewer --size 320x360 --frames 1 --out "$dir/img/$name" > /dev/null
  mv "$dir/img/${name}_full.png" "$dir/img/$name.png"
  jq -r --arg name "$name" --arg viewer "${viewer:-its camera}" '
    def r(n): (. * pow(10; n) | round) / pow(10; n);
    def ns(m): (m.trace_ms * m.threads_ * 1e6 / m.rays_total) | r(0);
    . as $j | ($j.threads) as $t
    | ($j.full + {threads_: $t, rays_total: ($j.full.rays | add)}) as $f
    | ($j.foveated + {threads_: $t, rays_total: ($j.foveated.rays | add)}) as $v
    | "| \($name) | \($j.triangles) | \($j.effects) | \($viewer) | \($j.frames) | \($f.total_ms | r(1)) | \($v.total_ms | r(1)) | \($j.speedup | r(2))x | \($j.content_speedup | r(2))x | \($j.speedup_parts.trace_speedup | r(2))x | \($j.speedup_parts.trace_of_content_speedup | r(2)) | \($j.speedup_parts.fixed_ms | r(1)) | \($j.speedup_parts.breakeven_full_ms // 0 | r(1)) | \(ns($f)) | \(ns($v)) |"
  ' "$dir/json/$name.json" >> "$dir/scenes.md"
  echo "bench/scenes.sh: $name done" >&2
done
{
  echo
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name _ _ _ <<< "$entry"
    echo "![$name: full render, 320x360](img/$name.png)"
  done
} >> "$dir/scenes.md"
echo "wrote $dir/scenes.md"
