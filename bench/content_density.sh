#!/usr/bin/env bash
# Content-aware density on the benchmark set (bench/scenes.sh's scenes and viewers):
# per scene and content contrast, `fovea render --mode both` on the FOVE eye at a
# centred and an off-centre gaze gives the primary rays as a fraction of the full
# render's, the points thinned, the density stage's time and PSNR per eccentricity
# ring against the full render at equal rays (one ray per pixel and per point).
# Writes DIR/content_density.md (headed by the command and this machine) and
# DIR/json/<scene>_<gaze>_c<C>.json.
# Usage: bench/content_density.sh [DIR [CONTRASTS [FRAMES]]]
#   (defaults: out/content_density "0 0.25 0.5 1" 3)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-out/content_density}
contrasts=${2:-0 0.25 0.5 1}
frames=${3:-3}
fovea=build/bin/fovea
[ -x "$fovea" ] || { echo "bench/content_density.sh: $fovea is missing: build first (scripts/run.sh)" >&2; exit 2; }
mkdir -p "$dir/json" out/cache
engine_glb=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
scenes=(  # name | --scene | viewer options (bench/scenes.sh's)
  "default|default|"
  "room|room|"
  "hall|hall|"
  "dense|dense|"
  "engine|$engine_glb|--pose 450,300,420 --look-at 0,-80,100"
)
gazes=("centre|640,720" "off-centre|320,400")
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
common=(--preset fove --mode both --interpolation msm --k 5 --frames "$frames" --cache-dir out/cache --json)
{
  echo "# Content-aware density on the benchmark set"
  echo
  echo "Machine: $(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB; $(date -u +%Y-%m-%d);" \
       "load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
  echo "Written by \`bench/content_density.sh $(printf '%q ' "$@" | sed 's/ $//')\`; per row \`$fovea render --scene SCENE VIEWER --gaze X,Y" \
       "--content-contrast C ${common[*]}\`."
  echo "Rays: the last frame's primary rays over the full render's (1 ray per pixel). PSNR in dB against the full"
  echo "render at equal rays, per ring (degrees from the gaze; the pixel-exact fovea is identical, so it is left out)."
  echo
  echo "| scene | gaze | content contrast | rays % of full | points thinned | density ms | 2.5-5 | 5-10 | 10-20 | 20-30 | 30-45 | >45 |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} >"$dir/content_density.md"
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene viewer <<<"$entry"
  if [ "$name" = engine ] && [ ! -f "$engine_glb" ]; then
    echo "bench/content_density.sh: $engine_glb is missing (assimp-testmodels): skipping engine" >&2
    continue
  fi
  for g in "${gazes[@]}"; do
    IFS='|' read -r gname gaze <<<"$g"
    for c in $contrasts; do
      echo "=== $name, $gname gaze, content contrast $c" >&2
      json="$dir/json/${name}_${gname}_c$c.json"
      # shellcheck disable=SC2086
      "$fovea" render --scene "$scene" $viewer --gaze "$gaze" --content-contrast "$c" "${common[@]}" >"$json"
      jq -r --arg name "$name" --arg gaze "$gname" --arg c "$c" '
        def r1: if . == null then "=" else . * 10 | round / 10 end;
        [.rings[] | select(.from_deg >= 2.5) | .psnr | r1] as $p
        | "| \($name) | \($gaze) | \($c) | \(.foveated.rays.primary / .full.rays.primary * 1000 | round / 10)"
          + " | \(.points_thinned) | \(.foveated.density_ms | r1) | \($p | join(" | ")) |"' "$json" \
        >>"$dir/content_density.md"
    done
  done
done
echo "wrote $dir/content_density.md" >&2
