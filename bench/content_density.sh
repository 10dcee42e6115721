#!/usr/bin/env bash
# Content-aware density and rays per point by contrast on the benchmark set (bench/scenes.sh's
# scenes and viewers), in parts, each writing its own file in DIR (headed by its command and
# this machine) and its JSON in DIR/json/:
#  detection (content_density.md): per scene, at a centred and an off-centre gaze, `fovea-eval
#    density` sweeps the density scale (eccentricity only, from denser than the thesis's to far
#    sparser) and content-aware density at scale 1 and at the sparsest scale the metric does not
#    see, its levers: the contrast that thins points, the contrast from which
#    a point casts all its rays (rays per point by contrast), and both from one contrast; it gives,
#    per kind, the smallest ray fraction at which the perceptual metric predicts P < 0.5 in every
#    ring the full render at the same rays per pixel does not already show, against a converged
#    reference (cached in out/cache/reference), and the content-aware row with the fewest rays at
#    eccentricity only's detection per ring at scale 1. The view: a CROP of the FOVE eye at its
#    pixels per degree (10.2 at the gaze), RAYS rays per point and per pixel.
#  levers (levers.md): from the detection part's JSON, per lever and contrast over its scenes, gazes and
#    scales, the rows where the lever makes a ring seen that eccentricity only at the same scale leaves
#    unseen, the largest rise of P, and the rays it keeps.
#  multiples (multiples.md): centred gaze, how many times above threshold each ring of the CROP is
#    (`fovea-eval density --ring-multiples`) at the thesis's scale 1, eccentricity only and thinned
#    from contrast 0.1, with nearest-neighbour and MSM reconstruction, beside the full render's.
#  cost (cost.md): what choosing the density costs in a product frame, per stage: `fovea render`
#    on the whole FOVE eye, thinning at one ray per point, rays by contrast (the default) at four and
#    sixteen and both levers at four, against eccentricity only's frame at the same rays per point.
#  rays (rays.md): rays per point by contrast, centred gaze: `fovea-eval density --ray-contrasts`
#    on the CROP at 16 rays per point and density scale 2, the primary rays against eccentricity
#    only at the same scale, and what the metric sees.
#  eccentricity (eccentricity.md): per scene and gaze, at eccentricity only's sparsest unseen scale
#    (from the detection part's JSON), rays by contrast from 1 with the contrast the same everywhere
#    and doubling every 30, 20 and 11.6 degrees of eccentricity (`--content-rays-doubling`): the ray
#    fraction and the rings the metric sees, as in the detection part.
#  doubling (doubling.md): the same doublings at the thesis's density (scale 1, where the product runs),
#    rays by contrast from the product's default contrast and from 1: per scene and gaze, the rings
#    the metric sees that eccentricity only at scale 1 leaves unseen, the largest rise of P, the ray fraction.
#  device-cost (cost_device.md): the same on the device trace, per stage: `hello_foveated --engine
#    gpu` through the layer and the simulated runtime on lavapipe (the scenes it loads: not engine,
#    whose viewer it cannot place), with content contrast 0.5 and without; the GPU ms of the
#    density's passes from XrFoveatedRendererDensityStatsFOVEART beside the trace and frame.
#  flicker (flicker.md): do the levers flicker? `fovea-eval motion` on the whole FOVE eye over the
#    built-in head and gaze motion, with both product histories (image, rays), thinning from content
#    contrast 0.1 at one ray per point and rays by contrast from 0.5 at four, each against eccentricity
#    only: the CSF-weighted flicker per ring against a converged reference sequence, its floor, and
#    the points and rays traced.
# Usage: bench/content_density.sh [--part detection|levers|multiples|cost|rays|eccentricity|doubling|device-cost|flicker]
#                                  [--scenes NAME,...]
#                                  [DIR [CROP [RAYS [REFERENCE_SPP]]]]
#   (defaults: every part, every scene; out/content_density 320x360 128 512). CROP 1280x1440 is
#   the whole eye, out to its widest eccentricities: about 5 minutes a scene on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
args=("$@")
parts=(detection levers multiples cost rays eccentricity doubling device-cost flicker)
if [ "${1:-}" = --part ]; then
  case "${2:-}" in
    detection | levers | multiples | cost | rays | eccentricity | doubling | device-cost | flicker) parts=("$2") ;;
    *) echo "bench/content_density.sh: --part detection, levers, multiples, cost, rays, eccentricity, doubling, device-cost" \
         "or flicker" >&2; exit 2 ;;
  esac
  shift 2
fi
only_scenes=""
if [ "${1:-}" = --scenes ]; then
  only_scenes=${2:?bench/content_density.sh: --scenes needs a list: default,room,hall,dense,engine}
  shift 2
fi
dir=${1:-out/content_density}
crop=${2:-320x360}
whole_eye=1280x1440  # a CROP of the FOVE eye's own size is the whole eye
rays=${3:-128}
reference_spp=${4:-512}
eval_bin=build/bin/fovea-eval
fovea=build/bin/fovea
hello=build/bin/hello_foveated
need() { results_need bench/content_density.sh "$@"; }
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
# jq: a row beside eccentricity only at its scale ($e), per ring both measure: the rise of P, and
# whether the row makes the ring seen (P >= 0.5) where eccentricity only leaves it unseen.
jq_against='def against($r; $e): [range(0; $r.rings_p_max | length)
    | select($r.rings_p_max[.] != null and $e.rings_p_max[.] != null)
    | {ring: ., rise: ($r.rings_p_max[.] - $e.rings_p_max[.]), new: ($r.rings_p_max[.] >= 0.5 and $e.rings_p_max[.] < 0.5)}];'
gazes=("centre|$((cw / 2)),$((ch / 2))" "off-centre|$((cw / 5)),$((ch / 5))")  # name | --gaze
scene_gazes() {  # per scene and gaze: name|scene|viewer|gaze name|gaze
  local entry g
  for entry in "${scenes[@]}"; do
    for g in "${gazes[@]}"; do echo "$entry|$g"; done
  done
}
# The rings' legend, then every row's largest P per ring: the table body in DETAILS (removed after),
# its columns before the rings named by HEAD ("scene | gaze | ..."), appended to MD.
every_row_appendix() {  # md details head
  local md=$1 details=$2 head=$3 columns
  columns=$(awk -F' [|] ' '{print NF + 8}' <<<"$head")
  {
    echo
    echo "Rings: 0: 0-2.5, 1: 2.5-5, 2: 5-10, 3: 10-20, 4: 20-30, 5: 30-45, 6: >45 degrees from the gaze."
    echo
    echo "## Every row: the largest P per ring"
    echo
    echo "| $head | 0-2.5 | 2.5-5 | 5-10 | 10-20 | 20-30 | 30-45 | >45 | unseen |"
    printf '|---%.0s' $(seq "$columns")
    echo "|"
    cat "$details"
  } >>"$md"
  rm -f "$details"
}
# The flicker runs: the whole FOVE eye over the built-in head and gaze motion, both product histories,
# against a converged reference sequence (fovea-eval motion), and the head of their tables.
flicker_frames=12
flicker_spp=32
flicker_motion=(--mode foveated --frames "$flicker_frames" --temporal image,rays --interpolation msm --k 5
                --reference-spp "$flicker_spp" --cache-dir out/cache --json)
flicker_table_head() {
  echo "| scene | history | density | points % | rays % | 0-2.5 | 2.5-5 | 5-10 | 10-20 | 20-30 | 30-45 | >45 |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
}
# One scene's flicker rows: eccentricity only (the first JSON of fovea-eval motion), then each
# lever's (the next JSONs, named by LEVERS, a JSON array) per history, then the reference's floor.
flicker_rows() {  # name levers off.json lever.json...
  local name=$1 levers=$2
  shift 2
  jq -r -s --arg name "$name" --argjson levers "$levers" '
    def r5: if . == null then "-" else . * 100000 | round / 100000 end;
    def rings: .rings | map(.flicker_csf | r5) | join(" | ");
    def pct($a; $b): if $b > 0 then $a / $b * 1000 | round / 10 else "-" end;
    . as $runs | .[0] as $off
    | (($off.tracks | keys[]) as $i | $off.tracks[$i] as $e
       | "| \($name) | \($e.temporal) | eccentricity only | 100 | 100 | \($e | rings) |",
         (range(1; $runs | length) as $k | $runs[$k].tracks[$i] as $t
          | "| \($name) | \($t.temporal) | \($levers[$k - 1]) | \(pct($t.points_by_frame[1:] | add; $e.points_by_frame[1:] | add))"
            + " | \(pct($t.primary_rays_by_frame[1:] | add; $e.primary_rays_by_frame[1:] | add)) | \($t | rings) |")),
      "| \($name) | | reference floor | | | \($off.reference.rings | map(.flicker_csf_floor | r5) | join(" | ")) |"' "$@"
}
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
  local scales=0.3,0.4,0.5,0.7,0.8,0.9,1,1.2,1.5,2,3,4 contrasts=0.1,0.25,0.5,1 ray_contrasts=0.25,0.5,1 both_contrasts=0.25,0.5,1
  local common=(--preset fove --crop "$crop" --rays-per-point "$rays" --reference-spp "$reference_spp" --interpolation msm
                --k 5 --scales "$scales" --contrasts "$contrasts" --ray-contrasts "$ray_contrasts"
                --both-contrasts "$both_contrasts" --content-at-unseen --cache-dir out/cache)
  local md="$dir/content_density.md" details name scene viewer gname gaze json
  {
    header "Content-aware density on the benchmark set, judged by the perceptual metric"
    echo "Per scene and gaze \`$eval_bin density --scene SCENE VIEWER --gaze X,Y ${common[*]}\`."
    echo
    if [ "$crop" = "$whole_eye" ]; then
      echo "The view is the whole FOVE eye ($whole_eye). Every image is measured against a converged reference at"
    else
      echo "The view is a $crop crop of the FOVE eye at its pixels per degree, around the gaze (CROP $whole_eye: the"
      echo "whole eye). Every image is measured against a converged reference at"
    fi
    echo "$reference_spp rays per pixel. A row is unseen when, in every ring where the full render at $rays rays per"
    echo "pixel stays below P = 0.5, the row's largest P stays below 0.5 too; rings the full render already shows are"
    echo "listed (its own noise hides foveation there). Ray %: the row's primary rays over the full render's at the"
    echo "same rays per pixel. Eccentricity only sweeps the density scale $scales (below 1: denser than the"
    echo "thesis's point set). Content-aware density, at scale 1 and at the sparsest of those scales that is unseen,"
    echo "sweeps the contrast that thins points (\"thin C\": $contrasts) or the one from which a point casts all its rays"
    echo "(\"rays C\": $ray_contrasts, fewer below it), or both from one contrast (\"both C\": $both_contrasts)."
    echo "\"none\": no row of that kind is unseen. The goal is 10 % or less. Same detection: the"
    echo "content-aware row with the fewest rays whose largest P exceeds eccentricity only's at scale 1 by at most"
    echo "0.01 in every ring (\`detected_no_more\`), and the rays it saves against that row."
    if [ "$crop" != "$whole_eye" ]; then
      echo "What choosing the density costs per stage: [cost.md](cost.md); rays per point by contrast: [rays.md](rays.md)."
    fi
    echo
    echo "| scene | gaze | rings the full render shows | eccentricity only: smallest unseen ray % (scale) | content-aware: smallest unseen ray % (lever, scale) | eccentricity only at scale 1: ray %, rings seen | content-aware at the same detection: ray % (lever), rays saved % |"
    echo "|---|---|---|---|---|---|---|"
  } >"$md"
  details=$(mktemp)
  while IFS='|' read -r name scene viewer gname gaze; do
    echo "=== $name, $gname gaze" >&2
    json="$dir/json/${name}_${gname}.json"
    # shellcheck disable=SC2086
    "$eval_bin" density --scene "$scene" $viewer --gaze "$gaze" "${common[@]}" >"$json" </dev/null
    jq -r --arg name "$name" --arg gaze "$gname" "$jq_rings"'
      def lever: if .kind == "rays" then "rays \(.content_rays)" elif .kind == "content" then "thin \(.content_contrast)"
        elif .kind == "both" then "both \(.content_contrast)" else "\(.density_scale)" end;
      def best($b): if $b == null then "none" else "\($b.ray_fraction | pct) (\($b | lever))" end;
      def best_at($b): if $b == null then "none" else "\($b.ray_fraction | pct) (\($b | lever), \($b.density_scale))" end;
      def fewer($a; $b): if $a == null then $b elif $b == null then $a elif $b.ray_fraction < $a.ray_fraction then $b else $a end;
      (.rows[] | select(.kind == "eccentricity" and .density_scale == 1)) as $s1
      | .content_at_eccentricity_detection as $m
      | "| \($name) | \($gaze) | \(seen(.full.rings_p_max)) | \(best(.best_eccentricity))"
        + " | \(best_at(fewer(fewer(.best_content; .best_rays); .best_both))) | \($s1.ray_fraction | pct), \(seen($s1.rings_p_max))"
        + " | \(if $m == null then "none" else "\($m.ray_fraction | pct) (\($m | lever)), \((1 - $m.ray_fraction / $s1.ray_fraction) | pct)" end) |"' \
      "$json" >>"$md"
    jq -r --arg name "$name" --arg gaze "$gname" '
      def r2: if . == null then "-" else . * 100 | round / 100 end;
      .rows[] | "| \($name) | \($gaze) | \(.kind) | \(.density_scale) | \(.content_contrast) | \(.content_rays) | \(.ray_fraction * 1000 | round / 10)"
        + " | \(.rings_p_max | map(r2) | join(" | ")) | \(if .unseen then "yes" else "no" end) |"' "$json" >>"$details"
  done < <(scene_gazes)
  every_row_appendix "$md" "$details" "scene | gaze | density | scale | thin C | rays C | ray %"
}

# Per lever and contrast, over the detection part's scenes, gazes and scales: what it adds that the
# metric sees, against eccentricity only at the same scale: levers.md.
levers_part() {
  local md="$dir/levers.md" entry name g json rows pairs=0
  rows=$(mktemp)
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name _ <<<"$entry"
    for g in centre off-centre; do
      json="$dir/json/${name}_$g.json"
      [ -f "$json" ] || continue
      pairs=$((pairs + 1))
      # Each content-aware row beside eccentricity only at its scale, per ring.
      jq -c --arg where "$name, $g" "$jq_against"'
        [.rows[] | select(.kind == "eccentricity")] as $ecc
        | .rows[] | select(.kind != "eccentricity") | . as $r
        | ($ecc[] | select(.density_scale == $r.density_scale)) as $e
        | against($r; $e) as $rings
        | {kind: $r.kind, contrast: (if $r.kind == "rays" then $r.content_rays else $r.content_contrast end),
           at: (if $r.density_scale < 1 then "below 1" elif $r.density_scale == 1 then "1" else "above 1" end),
           where: "\($where), \($r.density_scale)", new: ($rings | any(.new)), top: ($rings | max_by(.rise)),
           share: ($r.ray_fraction / $e.ray_fraction)}' "$json" >>"$rows"
    done
  done
  [ "$pairs" -gt 0 ] || { echo "bench/content_density.sh: no detection results in $dir/json: run --part detection first" >&2; exit 2; }
  {
    header "What each lever adds that the perceptual metric sees"
    echo "From the detection part's results in this directory ([content_density.md](content_density.md), $pairs scene"
    echo "and gaze pairs): every content-aware row beside eccentricity only at the same density scale, both against the"
    echo "same converged reference, at the thesis's density (scale 1) and at the sparsest scale at which eccentricity only is"
    echo "unseen where that is below 1. Newly seen: rows where a ring reaches P = 0.5 that eccentricity only leaves below it."
    echo "Largest rise: the largest P of any ring minus eccentricity only's, over every row of the lever. Ray %: the"
    echo "rows' rays as a share of eccentricity only's at the same scale, smallest to largest."
    echo
    echo "| lever | contrast | scale | rows | rows newly seen | largest rise of P (scene, gaze, scale, ring) | ray % of eccentricity only's |"
    echo "|---|---|---|---|---|---|---|"
    jq -r -s '
      def r2: . * 100 | round / 100;
      def pct: . * 1000 | round / 10;
      group_by([({content: 0, rays: 1, both: 2}[.kind]), .contrast, ({"below 1": 1, "1": 0, "above 1": 2}[.at])])[]
      | (max_by(.top.rise)) as $m
      | "| \(.[0].kind | if . == "content" then "thin" else . end) | \(.[0].contrast) | \(.[0].at) | \(length)"
        + " | \(map(select(.new)) | length) | \($m.top.rise | r2) (\($m.where), \($m.top.ring))"
        + " | \(map(.share) | min | pct) to \(map(.share) | max | pct) |"' "$rows"
    echo
    echo "Rings: 0: 0-2.5, 1: 2.5-5, 2: 5-10, 3: 10-20, 4: 20-30, 5: 30-45, 6: >45 degrees from the gaze."
  } >"$md"
  rm -f "$rows"
}

# Per scene, centred gaze, how many times above threshold each ring is at the thesis's density, by
# reconstruction, beside the full render's own: multiples.md.
multiples_part() {
  need "$eval_bin"
  local methods=("nearest|--interpolation nearest" "msm|--interpolation msm --k 5")
  local common=(--preset fove --crop "$crop" --gaze "$((cw / 2)),$((ch / 2))" --rays-per-point "$rays"
                --reference-spp "$reference_spp" --scales 1 --contrasts 0.1 --ring-multiples --cache-dir out/cache)
  local md="$dir/multiples.md" entry name scene viewer method mname moptions json
  {
    header "How far above threshold foveation is, ring by ring"
    echo "Per scene and reconstruction \`$eval_bin density --scene SCENE VIEWER METHOD ${common[*]}\`, METHOD"
    echo "\`--interpolation nearest\` or \`--interpolation msm --k 5\`."
    echo
    echo "The centred gaze. Threshold multiple: how many times the frame's difference from a converged reference at"
    echo "$reference_spp rays per pixel must be divided, in luminance, for the ring's largest P to fall to one half"
    echo "(\`--ring-multiples\`); under 1 the ring is unseen, 0: unseen even amplified 4096 times. Frames: the full"
    echo "render at $rays rays per pixel (where it is above 1, its own noise is seen); eccentricity-only density at"
    echo "the thesis's scale 1; content-aware thinning from contrast 0.1 at the same scale. Ray %: primary rays over"
    echo "the full render's."
    echo
    echo "| scene | frame | reconstruction | ray % | 0-2.5 | 2.5-5 | 5-10 | 10-20 | 20-30 | 30-45 | >45 |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
  } >"$md"
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    for method in "${methods[@]}"; do
      IFS='|' read -r mname moptions <<<"$method"
      echo "=== $name, multiples, $mname" >&2
      json="$dir/json/${name}_multiples_$mname.json"
      # shellcheck disable=SC2086
      "$eval_bin" density --scene "$scene" $viewer $moptions "${common[@]}" >"$json"
      jq -r --arg name "$name" --arg method "$mname" '
        def r2: if . == null then "-" elif . == 0 then "0" else . * 100 | round / 100 end;
        def multiples: .rings_threshold_multiple | map(r2) | join(" | ");
        (if $method == "nearest" then "| \($name) | full render | | 100 | \(.full | multiples) |" else empty end),
        (.rows[] | "| \($name) | \(if .kind == "eccentricity" then "eccentricity only, scale 1" else "thin 0.1, scale 1" end)"
          + " | \($method) | \(.ray_fraction * 1000 | round / 10) | \(multiples) |")' "$json" >>"$md"
    done
  done
  echo >>"$md"
  echo "Rings: degrees from the gaze." >>"$md"
}

# Per scene, content-aware density's CPU cost per stage in a product frame: cost.md.
cost_part() {
  need "$fovea"
  local md="$dir/cost.md"
  local settings=(  # name | options: each rays per point's eccentricity only (off) first, then its levers
    "off, 1 ray|--rays-per-point 1"
    "thin 0.1, 1 ray|--content-contrast 0.1 --rays-per-point 1"
    "thin 0.5, 1 ray|--content-contrast 0.5 --rays-per-point 1"
    "off, 4 rays|--content-rays 0 --rays-per-point 4"
    "rays 0.5 (default), 4 rays|--rays-per-point 4"
    "both 0.5, 4 rays|--content-contrast 0.5 --content-rays 0.5 --rays-per-point 4"
    "rays 0.5 doubling 30, 4 rays|--rays-per-point 4 --content-rays-doubling 30"
    "off, 16 rays|--content-rays 0 --rays-per-point 16"
    "rays 0.5 (default), 16 rays|--rays-per-point 16"
  )
  local entry name scene viewer setting sname soptions load json off_ms
  {
    header "What choosing the density costs, per stage, on the CPU"
    echo "The whole FOVE eye ($whole_eye), MSM k = 5, centred gaze: at one ray per point eccentricity only (off), and"
    echo "content contrast 0.1 (the GPU path's default) and 0.5 (thinning alone); at four and sixteen rays per point"
    echo "eccentricity only (\`--content-rays 0\`) and rays per point by contrast from 0.5, the products' default there"
    echo "(the per-point test also counts each point's rays); at four, both levers from contrast 0.5, and rays by"
    echo "contrast doubling every 30 degrees from the gaze (\`--content-rays-doubling 30\`):"
    echo "\`$fovea render --scene SCENE VIEWER --preset fove --mode foveated --interpolation msm --k 5 SETTING"
    echo "--frames 5 --cache-dir out/cache --json\`, its median frame (select, trace and"
    echo "reconstruction: frame ms) and that frame's \`density_stages_ms\`: levels, the tiles' levels from the last"
    echo "frame's luminance ranges; test, the per-point test (thinned or traced, and its rays); observe, the traced"
    echo "colours into their tiles' ranges; fill, the thinned points from their parents. Test and observe run inside the"
    echo "parallel trace pass: their time summed over the threads, divided by the threads. Density ms is the four's sum."
    echo "Rays % of full: primary rays over the full render's at the same rays per pixel. Frame % of off: the frame ms"
    echo "over eccentricity only's at the same rays per point, what the density nets in time. Load average"
    echo "(1 min) when each ran. The device trace's passes: [cost_device.md](cost_device.md)."
    echo
    echo "| scene | setting | levels ms | test ms | observe ms | fill ms | density ms | frame ms | density % of the frame | rays % of full | frame % of off | load |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  } >"$md"
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    for setting in "${settings[@]}"; do
      IFS='|' read -r sname soptions <<<"$setting"
      echo "=== $name, cost, $sname" >&2
      load=$(cut -d' ' -f1 /proc/loadavg)
      json="$dir/json/${name}_cost_${sname//[ ,.()]/_}.json"
      # shellcheck disable=SC2086
      "$fovea" render --scene "$scene" $viewer --preset fove --mode foveated --interpolation msm --k 5 $soptions \
        --frames 5 --cache-dir out/cache --json >"$json"
      [[ "$sname" = off,* ]] && off_ms=$(jq '.foveated.total_ms' "$json")
      jq -r --arg name "$name" --arg setting "$sname" --arg load "$load" --argjson off_ms "$off_ms" '
        def r2: . * 100 | round / 100;
        .foveated as $f | $f.density_stages_ms as $s
        | "| \($name) | \($setting) | \($s.levels | r2) | \($s.test | r2) | \($s.observe | r2) | \($s.fill | r2)"
          + " | \($f.density_ms | r2) | \($f.total_ms | r2) | \($f.density_ms / $f.total_ms * 1000 | round / 10)"
          + " | \($f.rays.primary / .pixels / .rays_per_point * 1000 | round / 10)"
          + " | \($f.total_ms / $off_ms * 1000 | round / 10) | \($load) |"' \
        "$json" >>"$md"
    done
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

# hello_foveated --engine gpu with the layer config's extra keys $1 (', "content_contrast": ...' or '')
# on SCENE ($2) for $3 frames into JSON $4: centred (fixed) foveation, the device trace, reconstruction
# on the GPU. Its config and log go to out/content_density_device/.
device_run() {
  local extra=$1 scene=$2 frames=$3 json=$4 work=out/content_density_device log
  log="$work/$(basename "${json%.json}").log"
  mkdir -p "$work"
  printf '{ "wait_for_tables": true, "log_level": "warn", "reconstruction": "gpu"%s }\n' "$extra" >"$work/config.json"
  results_sim_run "$PWD/$work/config.json" "$frames" \
    "$hello" --engine gpu --scene "$scene" --eye-size "$cw" "$ch" --density-scale 4 --interpolation msm --k 5 \
    --temporal rays --gaze-source none --json >"$json" 2>"$log" ||
    { echo "bench/content_density.sh: hello_foveated failed; its log is $log" >&2; exit 1; }
}

# Per scene, content density's GPU cost per pass on the device trace, on lavapipe: cost_device.md.
device_cost_part() {
  need "$hello"
  local md="$dir/cost_device.md" frames=8
  {
    header "What choosing the density costs, per pass, on the device trace (lavapipe)"
    echo "Lavapipe is Mesa's CPU rasteriser: these are the passes' work on llvmpipe on this machine's cores, not GPU"
    echo "times; they say what runs where and in what proportion, not how fast a GPU is. Per scene, \`$hello --engine gpu"
    echo "--scene SCENE --eye-size $cw $ch --density-scale 4 --interpolation msm --k 5 --temporal rays --gaze-source none"
    echo "--json\` through the layer and the simulated runtime (bench/results_lib.sh), $frames frames, layer config"
    echo "\`\"reconstruction\": \"gpu\", \"content_contrast\": 0.5\` and once without content density: both eyes, the"
    echo "device trace (the GPU sample engine traces the layer's device rays), centred foveation. A $cw x $ch eye at density"
    echo "scale 4 puts the pixel-exact fovea's edge inside the view, as the whole FOVE eye at scale 1 does. Temporal"
    echo "\"rays\": the GPU path's default history, the render cache, which takes the traced points' rays. The scenes"
    echo "hello_foveated loads from their own camera: not engine, whose viewer it cannot place."
    echo
    echo "From \`XrFoveatedRendererDensityStatsFOVEART\` (\`hello_foveated --json\`'s \`density\`), per finished frame,"
    echo "both eyes' sum, median over the frames: fill, the thinned points from their parents; contrast, the tiles'"
    echo "contrast for the next frame. Trace: the stats' \`traceMs\` on the device (the rays, the engine's trace, the"
    echo "resolve and the two passes); frame: both eyes' GPU time in all (\`gpu_eye_ms_per_frame\`). Rays, with content"
    echo "density and without, and thinned points (filled from their parents): the newest finished frame's, both eyes."
    echo "llvmpipe shares the cores with whatever else runs: under load its trace varies by tens of % from frame to"
    echo "frame, so the two trace columns differ by more than content density changes them; the fill and contrast"
    echo "columns are the passes' own time. The CPU trace's stages: [cost.md](cost.md). Load average (1 min) when each ran."
    echo
    echo "| scene | fill ms | contrast ms | density % of the trace | trace ms | trace ms without | frame ms | rays | rays without | rays % | thinned points | load |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  } >"$md"
  local entry name scene viewer load
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    [ -z "$viewer" ] || continue  # hello_foveated has no viewer pose: the scenes viewed from their own camera
    echo "=== $name, device cost" >&2
    load=$(cut -d' ' -f1 /proc/loadavg)
    device_run ', "content_contrast": 0.5' "$scene" "$frames" "$dir/json/${name}_cost_device.json"
    device_run '' "$scene" "$frames" "$dir/json/${name}_cost_device_off.json"
    jq -r -s --arg name "$name" --arg load "$load" '
      def r2: . * 100 | round / 100;
      def median: sort | .[(length - 1) / 2 | floor];
      def both($pairs): $pairs | map(add) | median;
      .[0] as $on | .[1] as $off | $on.density as $d
      | both($d.gpu_fill_ms_per_frame) as $fill | both($d.gpu_contrast_ms_per_frame) as $contrast
      | both($on.gpu_trace_ms_per_frame) as $trace | ($on.eyes | map(.rays) | add) as $rays
      | ($off.eyes | map(.rays) | add) as $rays_off
      | "| \($name) | \($fill | r2) | \($contrast | r2) | \(($fill + $contrast) / $trace * 1000 | round / 10)"
        + " | \($trace | r2) | \(both($off.gpu_trace_ms_per_frame) | r2) | \(both($on.gpu_eye_ms_per_frame) | r2)"
        + " | \($rays) | \($rays_off) | \($rays / $rays_off * 1000 | round / 10)"
        + " | \($d.eyes | map(.points_thinned) | add) | \($load) |"' \
      "$dir/json/${name}_cost_device.json" "$dir/json/${name}_cost_device_off.json" >>"$md"
  done
}

# Per scene, the flicker of thinned points over a head and gaze motion against eccentricity only: flicker.md.
flicker_part() {
  need "$eval_bin"
  local contrast=0.1 md="$dir/flicker.md" entry name scene viewer lever
  local common=("${flicker_motion[@]}")
  local levers=(  # name | its JSON's suffix | eccentricity only's options | the lever's
    "thin $contrast|$contrast|--content-contrast 0|--content-contrast $contrast"
    "rays 0.5, 4 rays|rays_4|--rays-per-point 4 --content-rays 0|--rays-per-point 4 --content-rays 0.5"
  )
  {
    header "Does content-aware density flicker? Its levers over a head and gaze motion"
    echo "Per scene and lever, \`$eval_bin motion --scene SCENE ${common[*]}\` with the lever's options and with"
    echo "eccentricity only's: the whole FOVE eye over the first $flicker_frames frames (70 Hz) of the built-in head and gaze motion,"
    echo "MSM k = 5, with each temporal history of the product: image (the CPU path's default) and rays (the render"
    echo "cache, the device path's). The levers: thinning from content contrast $contrast at one ray per point"
    echo "(\`--content-contrast $contrast\`), and rays per point by contrast from 0.5 at four rays per point, the products'"
    echo "default where a point casts several (\`--rays-per-point 4 --content-rays 0.5\`, against \`--content-rays 0\`)."
    echo "Flicker: the CSF-weighted frame-to-frame change of the error against a converged reference sequence of"
    echo "$flicker_spp rays per pixel (\`flicker_csf\`, per ring), and the reference's own (its floor). Points and rays:"
    echo "per frame, frames 2 on (the first has no last frame to measure), as % of eccentricity only's. The scenes"
    echo "viewed from their own camera."
    echo
    flicker_table_head
  } >"$md"
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    [ -z "$viewer" ] || continue  # the motion's head path starts at the scene's own camera
    for lever in "${levers[@]}"; do
      local lname suffix off_options on_options
      IFS='|' read -r lname suffix off_options on_options <<<"$lever"
      echo "=== $name, flicker, $lname" >&2
      # shellcheck disable=SC2086
      "$eval_bin" motion --scene "$scene" "${common[@]}" $off_options >"$dir/json/${name}_flicker_${suffix}_off.json"
      # shellcheck disable=SC2086
      "$eval_bin" motion --scene "$scene" "${common[@]}" $on_options >"$dir/json/${name}_flicker_$suffix.json"
      flicker_rows "$name" "[\"$lname\"]" "$dir/json/${name}_flicker_${suffix}_off.json" \
        "$dir/json/${name}_flicker_$suffix.json" >>"$md"
    done
  done
}

# Per scene and gaze, rays by contrast with the contrast doubling by eccentricity, at eccentricity
# only's sparsest unseen scale: eccentricity.md.
eccentricity_part() {
  need "$eval_bin"
  # 11.6: castleCSF's achromatic threshold doubling (its slowest eccentricity drop, 10^(0.026 e) at low frequency).
  local doublings=0,30,20,11.6
  local common=(--preset fove --crop "$crop" --rays-per-point "$rays" --reference-spp "$reference_spp" --interpolation msm
                --k 5 --contrasts --ray-contrasts 1 --rays-doublings "$doublings" --cache-dir out/cache)
  local md="$dir/eccentricity.md" details name scene viewer gname gaze src scale json
  {
    header "Rays per point by contrast and eccentricity on the benchmark set"
    echo "Per scene and gaze \`$eval_bin density --scene SCENE VIEWER --gaze X,Y --scales S --density-scale S ${common[*]}\`,"
    echo "S: eccentricity only's sparsest unseen density scale in [content_density.md](content_density.md)."
    echo
    echo "Rays per point by contrast from C = 1, with C the same everywhere (same C) or doubling every 30, 20 or"
    echo "11.6 degrees from the gaze, in steps (\`--content-rays-doubling\`: 2C from one step on, 4C from two). 11.6"
    echo "degrees is the rate of castleCSF's achromatic threshold, its slowest rise with eccentricity. Ray % and"
    echo "unseen as in [content_density.md](content_density.md): the row's primary rays over the full render's at"
    echo "$rays rays per pixel, and unseen when every ring the full render does not show stays below P = 0.5."
    echo "The goal is 10 % or less."
    echo
    echo "| scene | gaze | scale S | rings the full render shows | eccentricity only at S: ray %, rings seen | same C: ray %, rings seen | doubling 30: ray %, rings seen | doubling 20: ray %, rings seen | doubling 11.6: ray %, rings seen | smallest unseen ray % (doubling) |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
  } >"$md"
  details=$(mktemp)
  while IFS='|' read -r name scene viewer gname gaze; do
    src="$dir/json/${name}_${gname}.json"
    [ -f "$src" ] || { echo "bench/content_density.sh: $src is missing: run --part detection first" >&2; exit 2; }
    scale=$(jq -r '.best_eccentricity.density_scale // empty' "$src")
    if [ -z "$scale" ]; then
      echo "| $name | $gname | none | | | | | | | |" >>"$md"
      continue
    fi
    echo "=== $name, $gname gaze, rays by contrast and eccentricity at scale $scale" >&2
    json="$dir/json/${name}_${gname}_eccentricity.json"
    # shellcheck disable=SC2086
    "$eval_bin" density --scene "$scene" $viewer --gaze "$gaze" --scales "$scale" --density-scale "$scale" \
      "${common[@]}" >"$json" </dev/null
    jq -r --arg name "$name" --arg gaze "$gname" "$jq_rings"'
      def cell($r): if $r == null then "-" else "\($r.ray_fraction | pct), \(seen($r.rings_p_max) | if . == "" then "none" else . end)" end;
      .full as $full
      | [.rows[] | select(.kind == "rays")] as $rays
      | def at($d): first($rays[] | select(.content_rays_doubling_deg == $d)) // null;
      ([$rays[] | select(.unseen)] | min_by(.ray_fraction)) as $best
      | "| \($name) | \($gaze) | \(.rows[0].density_scale) | \(seen($full.rings_p_max)) | \(cell(.rows[0]))"
        + " | \(cell(at(0))) | \(cell(at(30))) | \(cell(at(20))) | \(cell(at(11.6)))"
        + " | \(if $best == null then "none" else "\($best.ray_fraction | pct) (\($best.content_rays_doubling_deg | if . == 0 then "same C" else . end))" end) |"' \
      "$json" >>"$md"
    jq -r --arg name "$name" --arg gaze "$gname" '
      def p: if . == null then "-" else . * 100 | round / 100 end;
      .rows[] | "| \($name) | \($gaze) | \(if .kind == "rays" then "rays, doubling \(.content_rays_doubling_deg)" else .kind end)"
        + " | \(.ray_fraction * 1000 | round / 10) | \(.rings_p_max | map(p) | join(" | ")) | \(if .unseen then "yes" else "no" end) |"' \
      "$json" >>"$details"
  done < <(scene_gazes)
  every_row_appendix "$md" "$details" "scene | gaze | row | ray %"
  eccentricity_flicker "$md"
}

# Does doubling every 30 degrees flicker? Over the flicker part's motion, rays by contrast from 0.5 at
# four rays per point with the doubling, beside that part's runs without it: appended to MD.
eccentricity_flicker() {  # md
  local md=$1 entry name scene viewer base
  local motion=("${flicker_motion[@]}" --rays-per-point 4 --content-rays 0.5 --content-rays-doubling 30)
  {
    echo
    echo "## Flicker over a head and gaze motion"
    echo
    echo "Per scene, \`$eval_bin motion --scene SCENE ${motion[*]}\` beside eccentricity only and rays by contrast"
    echo "from 0.5 without the doubling: [flicker.md](flicker.md)'s runs, with its measures (the CSF-weighted"
    echo "frame-to-frame change of the error per ring against a converged reference sequence, and that sequence's"
    echo "own) and its points and rays per frame as % of eccentricity only's."
    echo
    flicker_table_head
  } >>"$md"
  for entry in "${scenes[@]}"; do
    IFS='|' read -r name scene viewer <<<"$entry"
    [ -z "$viewer" ] || continue  # the motion's head path starts at the scene's own camera
    base="$dir/json/${name}_flicker_rays_4"
    [ -f "${base}_off.json" ] && [ -f "$base.json" ] ||
      { echo "bench/content_density.sh: ${base}*.json are missing: run --part flicker first" >&2; exit 2; }
    echo "=== $name, flicker, rays 0.5 doubling every 30 degrees" >&2
    "$eval_bin" motion --scene "$scene" "${motion[@]}" >"${base}_doubling_30.json"
    flicker_rows "$name" '["rays 0.5, 4 rays", "rays 0.5, 4 rays, doubling 30"]' "${base}_off.json" "$base.json" \
      "${base}_doubling_30.json" >>"$md"
  done
}

# Does the doubling add what the metric sees at the thesis's density, where the product runs? Per
# scene and gaze at scale 1, each contrast and doubling beside eccentricity only: doubling.md.
doubling_part() {
  need "$eval_bin"
  local contrasts=0.5,1 doublings=0,30,20
  local common=(--preset fove --crop "$crop" --rays-per-point "$rays" --reference-spp "$reference_spp" --interpolation msm
                --k 5 --scales 1 --density-scale 1 --contrasts --ray-contrasts "$contrasts" --rays-doublings "$doublings"
                --cache-dir out/cache)
  local md="$dir/doubling.md" details name scene viewer gname gaze json
  {
    header "Rays per point by contrast and eccentricity at the thesis's density"
    echo "Per scene and gaze \`$eval_bin density --scene SCENE VIEWER --gaze X,Y ${common[*]}\`."
    echo
    echo "At density scale 1, where the product runs, rays by contrast from C = 0.5 (the product's default) and"
    echo "from 1, with C the same everywhere (same C) or doubling every 30 or 20 degrees from the gaze"
    echo "(\`--content-rays-doubling\`), beside eccentricity only at scale 1, both against the same converged"
    echo "reference at $reference_spp rays per pixel. A cell: the row's primary rays as % of the full render's at $rays"
    echo "rays per pixel; the largest rise of P over eccentricity only's in any ring; and the rings newly seen,"
    echo "where the row reaches P = 0.5 and eccentricity only stays below it (none: nothing added that the"
    echo "metric sees)."
    echo
    echo "| scene | gaze | eccentricity only: ray %, rings seen | C 0.5 | C 0.5, doubling 30 | C 0.5, doubling 20 | C 1 | C 1, doubling 30 | C 1, doubling 20 |"
    echo "|---|---|---|---|---|---|---|---|---|"
  } >"$md"
  details=$(mktemp)
  while IFS='|' read -r name scene viewer gname gaze; do
    echo "=== $name, $gname gaze, rays by contrast and eccentricity at scale 1" >&2
    json="$dir/json/${name}_${gname}_doubling.json"
    # shellcheck disable=SC2086
    "$eval_bin" density --scene "$scene" $viewer --gaze "$gaze" "${common[@]}" >"$json" </dev/null
    jq -r --arg name "$name" --arg gaze "$gname" "$jq_rings$jq_against"'
      def r2: . * 100 | round / 100;
      (.rows[] | select(.kind == "eccentricity")) as $e
      | def cell($c; $d): first(.rows[] | select(.kind == "rays" and .content_rays == $c
                                               and .content_rays_doubling_deg == $d)) // null
          | if . == null then "-" else against(.; $e) as $rings
            | ($rings | map(.rise) | max | r2) as $rise
            | ($rings | map(select(.new) | .ring | tostring) | join(",")) as $new
            | "\(.ray_fraction | pct), \(if $rise > 0 then "+" else "" end)\($rise), \($new | if . == "" then "none" else . end)" end;
      "| \($name) | \($gaze) | \($e.ray_fraction | pct), \(seen($e.rings_p_max) | if . == "" then "none" else . end)"
      + " | \(cell(0.5; 0)) | \(cell(0.5; 30)) | \(cell(0.5; 20)) | \(cell(1; 0)) | \(cell(1; 30)) | \(cell(1; 20)) |"' \
      "$json" >>"$md"
    jq -r --arg name "$name" --arg gaze "$gname" '
      def p: if . == null then "-" else . * 100 | round / 100 end;
      .rows[] | "| \($name) | \($gaze) | \(if .kind == "rays" then "C \(.content_rays), doubling \(.content_rays_doubling_deg)" else .kind end)"
        + " | \(.ray_fraction * 1000 | round / 10) | \(.rings_p_max | map(p) | join(" | ")) | \(if .unseen then "yes" else "no" end) |"' \
      "$json" >>"$details"
  done < <(scene_gazes)
  every_row_appendix "$md" "$details" "scene | gaze | row | ray %"
}

if [ ! -f "$engine_glb" ]; then
  echo "bench/content_density.sh: $engine_glb is missing (assimp-testmodels): skipping engine" >&2
  unset 'scenes[4]'
fi
if [ -n "$only_scenes" ]; then
  kept=()
  for entry in "${scenes[@]}"; do
    [[ ",$only_scenes," == *",${entry%%|*},"* ]] && kept+=("$entry")
  done
  [ ${#kept[@]} -gt 0 ] || { echo "bench/content_density.sh: --scenes $only_scenes names no scene" >&2; exit 2; }
  scenes=("${kept[@]}")
fi
for part in "${parts[@]}"; do
  "${part//-/_}_part"
done
echo "wrote ${parts[*]} in $dir" >&2
