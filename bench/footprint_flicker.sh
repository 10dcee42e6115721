#!/usr/bin/env bash
# Aliasing flicker of a textured floor with and without the ray footprint on the GPU engine:
# GpuFootprint.TexturedFloorAt30DegFlickersLessWithTheFootprint (tests/engine/gpu_footprint_test.cpp)
# traces a fine checkerboard floor at 30 deg from the gaze along the built-in motion, one jittered
# ray per point each frame, with the footprint (XrFoveatedDeviceRayFootprintFOVEART) and without,
# and measures both against a converged disc average (eval::TemporalError). The test's harness
# is the measuring command; this runs it RUNS times and writes DIR/footprint_flicker.md (headed by
# the command, this machine and the Vulkan device) from the JSON line it prints.
# Usage: bench/footprint_flicker.sh [DIR [RUNS]]   (defaults: out/results 1; the test's
# rays are seeded, so a run repeats on one device); needs gpu_engine_tests built
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
dir=${1:-out/results}
runs=${2:-1}
tests=build/bin/gpu_engine_tests
filter=GpuFootprint.TexturedFloorAt30DegFlickersLessWithTheFootprint
results_need bench/footprint_flicker.sh "$tests"
mkdir -p "$dir"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
load_before=$(results_load)
for run in $(seq 1 "$runs"); do
  echo "footprint flicker: run $run of $runs" >&2
  "$tests" --gtest_filter="$filter" >"$work/run$run.log"
  sed -n 's/^\[ footprint \] //p' "$work/run$run.log" >"$work/run$run.json"
  [ -s "$work/run$run.json" ] || { echo "bench/footprint_flicker.sh: the test printed no numbers (skipped?):" >&2; cat "$work/run$run.log" >&2; exit 1; }
done
{
  echo "# Aliasing flicker with and without the ray footprint"
  echo
  results_machine
  echo "Vulkan device: $(jq -r .device "$work/run1.json"). Load average (1, 5, 15 min): $load_before before," \
       "$(results_load) after. $(results_written_by bench/footprint_flicker.sh "$@")"
  echo
  j="$work/run1.json"
  echo "\`$tests --gtest_filter=$filter\`, run $runs time(s) (its rays are seeded). A 256x256"
  echo "checkerboard of 2-texel squares repeated 64 times over a 40 m floor (4.9 mm squares), seen 35 deg down from"
  echo "1.6 m; a 20x20 patch of points $(jq -r .eccentricity_deg "$j") deg from the gaze on the FOVE 0 (disc radius"
  echo "$(jq -r .radius_px "$j") px, thesis eq. 4); one jittered ray per point each frame over $(jq -r .frames "$j") frames of the"
  echo "built-in motion, against $(jq -r .reference_rays "$j") jittered rays per point at level 0. Flicker: eval::TemporalError's"
  echo "flicker_rms in the 30-45 deg ring; error: its error_mse. The test asserts less flicker with the footprint."
  echo
  echo "| run | flicker with footprint | flicker without | error MSE with | error MSE without |"
  echo "|---|---|---|---|---|"
  for run in $(seq 1 "$runs"); do
    jq -r --arg run "$run" '"| \($run) | \(.flicker_rms_with) | \(.flicker_rms_without) | \(.error_mse_with) | \(.error_mse_without) |"' \
      "$work/run$run.json"
  done
} >"$dir/footprint_flicker.md"
echo "wrote $dir/footprint_flicker.md" >&2
