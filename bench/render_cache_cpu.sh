#!/usr/bin/env bash
# What the render cache (temporal "rays") costs on the CPU path against the image history, frame
# by frame: `fovea render` holds a view still for FRAMES frames of the default scene on the whole
# FOVE eye, once with each history, and reports each frame's time and the rays the cache keeps
# (a ray leaves it after 32 frames). Writes DIR/render_cache_cpu.md, headed by its command and
# this machine.
# Usage: bench/render_cache_cpu.sh [DIR [FRAMES]]   (defaults: out/results 36); needs fovea built
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
dir=${1:-out/results}
frames=${2:-36}
fovea=build/bin/fovea
results_need bench/render_cache_cpu.sh "$fovea"
mkdir -p "$dir" out/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
load_before=$(results_load)
command="$fovea render --scene default --preset fove --mode foveated --interpolation msm --k 5 --frames $frames --cache-dir out/cache --json --temporal"
for temporal in image rays; do
  echo "render cache cost: $frames frames with --temporal $temporal" >&2
  $command "$temporal" >"$work/$temporal.json"
done
{
  echo "# The render cache on the CPU path, frame by frame"
  echo
  results_machine
  echo "Load average (1, 5, 15 min): $load_before before, $(results_load) after. $(results_written_by bench/render_cache_cpu.sh "$@")"
  echo
  echo "\`$command image|rays\`: the default scene's own view held still for $frames frames, the whole FOVE eye"
  echo "(1280x1440), MSM k = 5, one ray per point. Frame ms: select, trace and reconstruction with the history"
  echo "(\`frames_total_ms\`); kept rays: the render cache's rays after the frame (\`frames_cached_rays\`). Every frame"
  echo "filters all kept rays into the pixels, so its cost grows with them until rays start leaving at 32 frames."
  echo "A moving head also drops the rays that leave the view or are covered."
  echo
  echo "| frame | image ms | rays ms | rays / image | kept rays (millions) |"
  echo "|---|---|---|---|---|"
  jq -rn --slurpfile i "$work/image.json" --slurpfile r "$work/rays.json" '
    def r1: . * 10 | round / 10;
    def r2: . * 100 | round / 100;
    ($i[0].foveated.frames_total_ms) as $im | ($r[0].foveated.frames_total_ms) as $rm
    | ($r[0].foveated.frames_cached_rays) as $kept
    | range(0; $im | length)
    | select(. == 0 or . == 1 or . == 3 or . == 7 or . == 15 or . == 23 or . == 31 or . == 32 or . == ($im | length) - 1)
    | "| \(. + 1) | \($im[.] | r1) | \($rm[.] | r1) | \($rm[.] / $im[.] | r1) | \($kept[.] / 1e6 | r2) |"'
} >"$dir/render_cache_cpu.md"
echo "wrote $dir/render_cache_cpu.md" >&2
