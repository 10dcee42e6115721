#!/usr/bin/env bash
# Content-aware against eccentricity-only density on the benchmark set (bench/scenes.sh's scenes
# and viewers), judged by the perceptual metric: per scene, at a centred and an off-centre gaze,
# `fovea-eval density` sweeps the density scale (eccentricity only) and the content contrast
# (content-aware, at scale 1) and gives, per kind, the smallest ray fraction at which the metric
# predicts P < 0.5 in every ring the full render at the same rays per pixel does not already show,
# against a converged reference (cached in out/cache/reference). The view: a CROP of the FOVE eye
# at its pixels per degree (10.2 at the gaze), RAYS rays per point and per pixel. Then, per scene,
# what choosing the density costs in a product frame: `fovea render` on the whole FOVE eye at one
# ray per point, content contrast 0.5, density_ms against the frame's ms (load average beside it).
# Writes DIR/content_density.md (headed by the command and this machine) and DIR/json/.
# Usage: bench/content_density.sh [DIR [CROP [RAYS [REFERENCE_SPP]]]]
#   (defaults: out/content_density 320x360 128 512)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-out/content_density}
crop=${2:-320x360}
rays=${3:-128}
reference_spp=${4:-512}
eval_bin=build/bin/fovea-eval
fovea=build/bin/fovea
for b in "$eval_bin" "$fovea"; do
  [ -x "$b" ] || { echo "bench/content_density.sh: $b is missing: build first (scripts/run.sh)" >&2; exit 2; }
done
mkdir -p "$dir/json" out/cache
engine_glb=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
scenes=(  # name | --scene | viewer options (bench/scenes.sh's)
  "default|default|"
  "room|room|"
  "hall|hall|"
  "dense|dense|"
  "engine|$engine_glb|--pose 450,300,420 --look-at 0,-80,100"
)
cw=${crop%x*}
ch=${crop#*x}
gazes=("centre|$((cw / 2)),$((ch / 2))" "off-centre|$((cw / 5)),$((ch / 5))")
scales=1,1.5,2,3,4
contrasts=0.25,0.5,1
common=(--preset fove --crop "$crop" --rays-per-point "$rays" --reference-spp "$reference_spp" --interpolation msm --k 5
        --scales "$scales" --contrasts "$contrasts" --cache-dir out/cache)
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
md="$dir/content_density.md"
{
  echo "# Content-aware density on the benchmark set, judged by the perceptual metric"
  echo
  echo "Machine: $(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB; $(date -u +%Y-%m-%d);" \
       "load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
  echo "Written by \`bench/content_density.sh $(printf '%q ' "$@" | sed 's/ $//')\`; per scene and gaze" \
       "\`$eval_bin density --scene SCENE VIEWER --gaze X,Y ${common[*]}\`."
  echo
  echo "The view is a $crop crop of the FOVE eye at its pixels per degree (the whole eye at $rays rays per pixel and its"
  echo "reference would take hours on this machine). Every image is measured against a converged reference at"
  echo "$reference_spp rays per pixel. A row is unseen when, in every ring where the full render at $rays rays per"
  echo "pixel stays below P = 0.5, the row's largest P stays below 0.5 too; rings the full render already shows are"
  echo "listed (its own noise hides foveation there). Ray %: the row's primary rays over the full render's at the"
  echo "same rays per pixel. Eccentricity only sweeps the density scale $scales; content-aware the contrast $contrasts"
  echo "at scale 1. \"none\": no row of that kind is unseen. The goal is 10 % or less."
  echo
  echo "| scene | gaze | rings the full render shows | eccentricity only: smallest unseen ray % (scale) | content-aware: smallest unseen ray % (contrast) | eccentricity only at scale 1: ray %, rings seen |"
  echo "|---|---|---|---|---|---|"
} >"$md"
details=$(mktemp)
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene viewer <<<"$entry"
  if [ "$name" = engine ] && [ ! -f "$engine_glb" ]; then
    echo "bench/content_density.sh: $engine_glb is missing (assimp-testmodels): skipping engine" >&2
    continue
  fi
  for g in "${gazes[@]}"; do
    IFS='|' read -r gname gaze <<<"$g"
    echo "=== $name, $gname gaze" >&2
    json="$dir/json/${name}_${gname}.json"
    # shellcheck disable=SC2086
    "$eval_bin" density --scene "$scene" $viewer --gaze "$gaze" "${common[@]}" >"$json"
    jq -r --arg name "$name" --arg gaze "$gname" '
      def pct: . * 1000 | round / 10;
      def seen($rings): [$rings | to_entries[] | select(.value != null and .value >= 0.5) | .key] | map(tostring) | join(",");
      def best($b; $key): if $b == null then "none" else "\($b.ray_fraction | pct) (\($b[$key]))" end;
      (.rows[] | select(.kind == "eccentricity" and .density_scale == 1)) as $s1
      | "| \($name) | \($gaze) | \(seen(.full.rings_p_max)) | \(best(.best_eccentricity; "density_scale"))"
        + " | \(best(.best_content; "content_contrast")) | \($s1.ray_fraction | pct), \(seen($s1.rings_p_max)) |"' \
      "$json" >>"$md"
    jq -r --arg name "$name" --arg gaze "$gname" '
      def r2: if . == null then "-" else . * 100 | round / 100 end;
      .rows[] | "| \($name) | \($gaze) | \(.kind) | \(.density_scale) | \(.content_contrast) | \(.ray_fraction * 1000 | round / 10)"
        + " | \(.rings_p_max | map(r2) | join(" | ")) | \(if .unseen then "yes" else "no" end) |"' "$json" >>"$details"
  done
done
{
  echo
  echo "Rings: 0: 0-2.5, 1: 2.5-5, 2: 5-10, 3: 10-20, 4: 20-30, 5: 30-45, 6: >45 degrees from the gaze."
  echo
  echo "## Every row: the largest P per ring"
  echo
  echo "| scene | gaze | density | scale | contrast | ray % | 0-2.5 | 2.5-5 | 5-10 | 10-20 | 20-30 | 30-45 | >45 | unseen |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  cat "$details"
  echo
  echo "## What choosing the density costs"
  echo
  echo "The whole FOVE eye (1280x1440), one ray per point, MSM k = 5, content contrast 0.5, centred gaze: the"
  echo "median of 5 frames of \`$fovea render --scene SCENE VIEWER --preset fove --mode foveated --interpolation msm --k 5"
  echo "--content-contrast 0.5 --frames 5 --cache-dir out/cache --json\`; density_ms is content-aware density's part of"
  echo "select and trace. Load average (1 min) when each ran."
  echo
  echo "| scene | density ms | frame ms | density % of the frame | rays % of full | load |"
  echo "|---|---|---|---|---|---|"
} >>"$md"
rm -f "$details"
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene viewer <<<"$entry"
  [ "$name" = engine ] && [ ! -f "$engine_glb" ] && continue
  load=$(cut -d' ' -f1 /proc/loadavg)
  # shellcheck disable=SC2086
  "$fovea" render --scene "$scene" $viewer --preset fove --mode foveated --interpolation msm --k 5 \
    --content-contrast 0.5 --frames 5 --cache-dir out/cache --json >"$dir/json/${name}_cost.json"
  jq -r --arg name "$name" --arg load "$load" '
    def r1: . * 10 | round / 10;
    "| \($name) | \(.foveated.density_ms | r1) | \(.foveated.total_ms | r1) | \(.foveated.density_ms / .foveated.total_ms * 1000 | round / 10)"
    + " | \(.foveated.rays.primary / .pixels * 1000 | round / 10) | \($load) |"' "$dir/json/${name}_cost.json" >>"$md"
done
echo "wrote $md" >&2
