#!/usr/bin/env bash
# The thesis check as pictures: what the perceptual metric sees at the density scales around its
# 50 % crossing and at the thesis's user study's (Table 3). The view is the thesis check's
# (tests/eval/thesis_density_test.cpp): the centre 256x256 crop of the thesis preset's view at its
# pixels per degree, the built-in scene's dark pillars against the lit corridor end, the gaze at the
# crop's centre, nearest neighbour over the pixel grid where the density is a point per pixel or
# more, 128 rays per point, a converged reference at 1024 rays per pixel, exposed as the whole view
# shows the crop (fovea-eval density meters a crop's whole view). `fovea-eval density --out` writes
# each frame on the view's display and P per pixel (black 0, white 1); DIR/thesis_check.md lays them
# side by side with each scale's ray fraction and largest P, headed by its command and this machine.
# Usage: bench/thesis_check.sh [DIR]   (default docs/results/thesis_check; a minute on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
dir=${1:-docs/results/thesis_check}
scales=0.7,0.8,1,1.75,3
[ -x build/bin/fovea-eval ] ||
  { echo "bench/thesis_check.sh: build/bin/fovea-eval is missing: build first (scripts/run.sh)" >&2; exit 2; }
mkdir -p "$dir/images" out/cache
load=$(results_load)
command=(build/bin/fovea-eval density --preset thesis --crop 256x256 --rays-per-point 128 --reference-spp 1024
  --interpolation nearest --pattern pixel-grid --scales "$scales" --contrasts 1
  --cache-dir out/cache --out "$dir/images/crop")
"${command[@]}" > "$dir/thesis_check.json"

{
  echo "# The thesis check: what the perceptual metric sees"
  echo
  results_machine
  echo "Load average (1, 5, 15 min) $load at the start. $(results_written_by bench/thesis_check.sh "$@")"
  echo
  echo "\`${command[*]}\`"
  echo
  json=$dir/thesis_check.json
  echo "The centre 256x256 crop of the thesis preset's view, $(jq '.pixels_per_deg * 10 | round / 10' "$json") pixels"
  echo "per degree at the gaze (the crop's centre), its corners at 9.4 degrees; nearest neighbour at"
  echo "$(jq '.rays_per_point' "$json") rays per point, each frame against a converged reference at"
  echo "$(jq '.reference_spp' "$json") rays per pixel. P: the metric's detection probability per pixel (black 0,"
  echo "white 1); the image's largest P decides. The thesis's users noticed foveation half the time at density"
  echo "scale 1.75 ± 0.35 (NN, Table 3). The metric sees the first Poisson points that replace the pixel grid,"
  echo "in the crop's corners from scale 0.76: the one-pixel jaggies they leave along the dark edge above the lit"
  echo "corridor end, a few pixels from the top (zoom into the frames' top corners to see them), and, from"
  echo "scale 1, along the pillars' edges near the bottom"
  echo "([the thesis check](../../lab/perceptual_metric.md#the-thesis-check))."
  echo
  echo "| density | ray % | largest P | frame | P |"
  echo "|---|---|---|---|---|"
  jq -r '
    def pct: . * 1000 | round / 10;
    def name: split("/") | last;
    def density: if .kind == "eccentricity" then "scale \(.density_scale)"
                 else "content contrast \(.content_contrast) at scale \(.density_scale)" end;
    "| reference |  |  | ![](images/\(.full.images[0] | name)) |  |",
    "| full render | 100 | \(.full.p_max * 100 | round / 100) | ![](images/\(.full.images[1] | name)) | ![](images/\(.full.images[2] | name)) |",
    (.rows[] |
      "| \(density) | \(.ray_fraction | pct) | \(.p_max * 100 | round / 100) | ![](images/\(.images[0] | name)) | ![](images/\(.images[1] | name)) |")
  ' "$dir/thesis_check.json"
} > "$dir/thesis_check.md"
echo "bench/thesis_check.sh: wrote $dir/thesis_check.md"
