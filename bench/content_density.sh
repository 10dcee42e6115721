#!/usr/bin/env bash
# Content-aware density and rays per point by contrast on the benchmark set (bench/scenes.sh's
# scenes and viewers), in three parts, each writing its own file in DIR (headed by its command and
# this machine) and its JSON in DIR/json/:
#  detection (content_density.md): per scene, at a centred and an off-centre gaze, `fovea-eval
#    density` sweeps the density scale (eccentricity only) and the content contrast (content-aware,
#    at scale 1) and gives, per kind, the smallest ray fraction at which the perceptual metric
#    predicts P < 0.5 in every ring the full render at the same rays per pixel does not already
#    show, against a converged reference (cached in out/cache/reference), and the content-aware
#    row with the fewest rays at eccentricity only's detection per ring. The view: a CROP of the
#    FOVE eye at its pixels per degree (10.2 at the gaze), RAYS rays per point and per pixel.
#  cost (cost.md): what choosing the density costs in a product frame, per stage: `fovea render`
#    on the whole FOVE eye at one ray per point, content contrast 0.5, against the frame's ms.
#  rays (rays.md): rays per point by contrast, centred gaze: `fovea-eval density --ray-contrasts`
#    on the CROP at 16 rays per point and density scale 2, the primary rays against eccentricity
#    only at the same scale, and what the metric sees.
# Usage: bench/content_density.sh [--part detection|cost|rays] [DIR [CROP [RAYS [REFERENCE_SPP]]]]
#   (defaults: every part; out/content_density 320x360 128 512)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
args=("$@")
parts=(detection cost rays)
if [ "${1:-}" = --part ]; then
  case "${2:-}" in detection | cost | rays) parts=("$2") ;; *) echo "bench/content_density.sh: --part detection, cost or rays" >&2; exit 2 ;; esac
  shift 2
fi
dir=${1:-out/content_density}
crop=${2:-320x360}
rays=${3:-128}
reference_spp=${4:-512}
eval_bin=build/bin/fovea-eval
fovea=build/bin/fovea
need() {
  [ -x "$1" ] || { echo "bench/content_density.sh: $1 is missing: build first (scripts/run.sh)" >&2; exit 2; }
}
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
# jq: a fraction as a percentage to 0.1, and the rings (their indices) where P reaches 0.5.
jq_rings='def pct: . * 1000 | round / 10;
  def seen($rings): [$rings | to_entries[] | select(.value != null and .value >= 0.5) | .key] | map(tostring) | join(",");'
header() {  # the title, then this machine, the load and the command
  echo "# $1"
  echo
  results_machine
  echo "Load average (1, 5, 15 min) $(results_load) at the start. $(results_written_by bench/content_density.sh "${args[@]}")"
  echo
}

# Per scene and gaze, the smallest unseen ray fraction of each kind: content_density.md.
detection_part() {
  need "$eval_bin"
  local gazes=("centre|$((cw / 2)),$((ch / 2))" "off-centre|$((cw / 5)),$((ch / 5))")
  local scales=1,1.5,2,3,4 contrasts=0.1,0.25,0.5,1
  local common=(--preset fove --crop "$crop" --rays-per-point "$rays" --reference-spp "$reference_spp" --interpolation msm
                --k 5 --scales "$scales" --contrasts "$contrasts" --cache-dir out/cache)
  local md="$dir/content_density.md" details
  {
    header "Content-aware density on the benchmark set, judged by the perceptual metric"
    echo "Per scene and gaze \`$eval_bin density --scene SCENE VIEWER --gaze X,Y ${common[*]}\`."
    echo
    echo "The view is a $crop crop of the FOVE eye at its pixels per degree (the whole eye at $rays rays per pixel and its"
    echo "reference would take hours on this machine). Every image is measured against a converged reference at"
    echo "$reference_spp rays per pixel. A row is unseen when, in every ring where the full render at $rays rays per"
    echo "pixel stays below P = 0.5, the row's largest P stays below 0.5 too; rings the full render already shows are"
    echo "listed (its own noise hides foveation there). Ray %: the row's primary rays over the full render's at the"
    echo "same rays per pixel. Eccentricity only sweeps the density scale $scales; content-aware the contrast $contrasts"
    echo "at scale 1. \"none\": no row of that kind is unseen. The goal is 10 % or less. Same detection: the"
    echo "content-aware row with the fewest rays whose largest P exceeds eccentricity only's at scale 1 by at most"
    echo "0.01 in every ring (\`detected_no_more\`), and the rays it saves against that row. What choosing the density"
    echo "costs per stage: [cost.md](cost.md); rays per point by contrast: [rays.md](rays.md)."
    echo
    echo "| scene | gaze | rings the full render shows | eccentricity only: smallest unseen ray % (scale) | content-aware: smallest unseen ray % (contrast) | eccentricity only at scale 1: ray %, rings seen | content-aware at the same detection: ray % (contrast), rays saved % |"
    echo "|---|---|---|---|---|---|---|"
  } >"$md"
  details=$(mktemp)
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    for g in "${gazes[@]}"; do
      IFS='|' read -r gname gaze <<<"$g"
      echo "=== $name, $gname gaze" >&2
      json="$dir/json/${name}_${gname}.json"
      # shellcheck disable=SC2086
      "$eval_bin" density --scene "$scene" $viewer --gaze "$gaze" "${common[@]}" >"$json"
      jq -r --arg name "$name" --arg gaze "$gname" "$jq_rings"'
        def best($b; $key): if $b == null then "none" else "\($b.ray_fraction | pct) (\($b[$key]))" end;
        (.rows[] | select(.kind == "eccentricity" and .density_scale == 1)) as $s1
        | .content_at_eccentricity_detection as $m
        | "| \($name) | \($gaze) | \(seen(.full.rings_p_max)) | \(best(.best_eccentricity; "density_scale"))"
          + " | \(best(.best_content; "content_contrast")) | \($s1.ray_fraction | pct), \(seen($s1.rings_p_max))"
          + " | \(if $m == null then "none" else "\($m.ray_fraction | pct) (\($m.content_contrast)), \((1 - $m.ray_fraction / $s1.ray_fraction) | pct)" end) |"' \
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
  } >>"$md"
  rm -f "$details"
}

# Per scene, content-aware density's CPU cost per stage in a product frame: cost.md.
cost_part() {
  need "$fovea"
  local md="$dir/cost.md"
  {
    header "What choosing the density costs, per stage, on the CPU"
    echo "The whole FOVE eye (1280x1440), one ray per point, MSM k = 5, content contrast 0.5, centred gaze:"
    echo "\`$fovea render --scene SCENE VIEWER --preset fove --mode foveated --interpolation msm --k 5"
    echo "--content-contrast 0.5 --frames 5 --cache-dir out/cache --json\`, its median frame (select, trace and"
    echo "reconstruction: frame ms) and that frame's \`density_stages_ms\`: levels, the tiles' levels from the last"
    echo "frame's luminance ranges; test, the per-point test (thinned or traced); observe, the traced colours into their"
    echo "tiles' ranges; fill, the thinned points from their parents. Test and observe run inside the parallel trace pass:"
    echo "their time summed over the threads, divided by the threads. Density ms is the four's sum. Load average (1 min)"
    echo "when each ran."
    echo
    echo "| scene | levels ms | test ms | observe ms | fill ms | density ms | frame ms | density % of the frame | rays % of full | load |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
  } >"$md"
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    echo "=== $name, cost" >&2
    load=$(cut -d' ' -f1 /proc/loadavg)
    # shellcheck disable=SC2086
    "$fovea" render --scene "$scene" $viewer --preset fove --mode foveated --interpolation msm --k 5 \
      --content-contrast 0.5 --frames 5 --cache-dir out/cache --json >"$dir/json/${name}_cost.json"
    jq -r --arg name "$name" --arg load "$load" '
      def r2: . * 100 | round / 100;
      .foveated as $f | $f.density_stages_ms as $s
      | "| \($name) | \($s.levels | r2) | \($s.test | r2) | \($s.observe | r2) | \($s.fill | r2) | \($f.density_ms | r2)"
        + " | \($f.total_ms | r2) | \($f.density_ms / $f.total_ms * 1000 | round / 10)"
        + " | \($f.rays.primary / .pixels * 1000 | round / 10) | \($load) |"' "$dir/json/${name}_cost.json" >>"$md"
  done
}

# Per scene, centred gaze, rays per point by contrast against eccentricity only at the same scale: rays.md.
rays_part() {
  need "$eval_bin"
  local ray_contrasts=0.25,0.5,1
  local common=(--preset fove --crop "$crop" --rays-per-point 16 --density-scale 2 --reference-spp "$reference_spp"
                --interpolation msm --k 5 --scales 2 --contrasts 1 --ray-contrasts "$ray_contrasts" --cache-dir out/cache)
  local md="$dir/rays.md"
  {
    header "Rays per point by contrast on the benchmark set"
    echo "Per scene, centred gaze: \`$eval_bin density --scene SCENE VIEWER --gaze $((cw / 2)),$((ch / 2)) ${common[*]}\`."
    echo
    echo "A $crop crop of the FOVE eye at its pixels per degree, 16 rays per point, density scale 2. Each rays-by-contrast"
    echo "row (contrast C from which a point casts all its rays, \`--content-rays C\` in \`fovea render\`) against"
    echo "eccentricity only at the same scale: its primary rays, as % of eccentricity only's and of the full render's at"
    echo "16 rays per pixel, and the rings where the metric's largest P reaches 0.5 against the $reference_spp-ray reference"
    echo "(seen), beside the rings the full render at 16 rays per pixel already shows (its own noise)."
    echo
    echo "| scene | full render: rings seen | eccentricity only: ray % of full, rings seen | rays from C | ray % of eccentricity only | ray % of full | rings seen |"
    echo "|---|---|---|---|---|---|---|"
  } >"$md"
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    echo "=== $name, rays by contrast" >&2
    json="$dir/json/${name}_rays.json"
    # shellcheck disable=SC2086
    "$eval_bin" density --scene "$scene" $viewer --gaze "$((cw / 2)),$((ch / 2))" "${common[@]}" >"$json"
    jq -r --arg name "$name" "$jq_rings"'
      .full as $full | (.rows[] | select(.kind == "eccentricity")) as $e
      | .rows[] | select(.kind == "rays")
      | "| \($name) | \(seen($full.rings_p_max)) | \($e.ray_fraction | pct), \(seen($e.rings_p_max)) | \(.content_rays)"
        + " | \(.ray_fraction / $e.ray_fraction | pct) | \(.ray_fraction | pct) | \(seen(.rings_p_max)) |"' "$json" >>"$md"
  done
  echo >>"$md"
  echo "Rings: 0: 0-2.5, 1: 2.5-5, 2: 5-10, 3: 10-20, 4: 20-30, 5: 30-45, 6: >45 degrees from the gaze." >>"$md"
}

if [ ! -f "$engine_glb" ]; then
  echo "bench/content_density.sh: $engine_glb is missing (assimp-testmodels): skipping engine" >&2
  unset 'scenes[4]'
fi
for part in "${parts[@]}"; do
  "${part}_part"
done
echo "wrote ${parts[*]} in $dir" >&2
