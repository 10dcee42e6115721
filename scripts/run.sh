#!/usr/bin/env bash
# The README's main job: installs what is missing, builds, and runs the most
# complete FoveaRT pipeline on built-in defaults. Everything lands in out/.
#   1. the FOVE point set: Table 1 counts, picture, curves
#   2. the sample engine: full versus foveated ray tracing of the default scene,
#      and the quick price list (what each setting costs and buys per ring)
#   3. hello_foveated through the FoveaRT layer on the simulated FOVE headset
#      (real OpenXR loader, Vulkan on lavapipe, 120 Hz simulated gaze), with
#      both eyes' composed frames captured
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
bash scripts/setup.sh
# Same tree and flags as `scripts/test.sh --plain`.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out/cache out/frames
export XDG_CACHE_HOME="$root/out/cache"   # the layer caches its tables in $XDG_CACHE_HOME/foveart

echo "=== 1/3 FOVE point set -> out/pointset.json, out/pointset_centred.png, out/curves/"
build/bin/fovea pointset --preset fove --cache out/cache --png out/pointset_centred.png \
  --curves out/curves --json > out/pointset.json
jq -r '"points \(.total) total, \(.on_screen_centred) on screen at centred gaze (\(100*.fraction_centred*10|round/10)% of \(.pixels) px); table \(.table_bytes/1e6|round) MB"' out/pointset.json

echo "=== 2/3 default scene, full vs foveated -> out/render.json, out/render_*.png"
build/bin/fovea render --scene default --preset fove --mode both --method msm --k 5 \
  --cache out/cache --out out/render --json > out/render.json
jq -r '"speedup \(.speedup*100|round/100)x (scene content allows \(.content_speedup*100|round/100)x: overhead \(.overhead_fraction*1000|round/10)%), agreement with the full frame (two noisy images, not accuracy: see the price list) PSNR \(.psnr*10|round/10) dB, SSIM \(.ssim*1000|round/1000)"' out/render.json

echo "=== 2b/3 quick price list of the default scene -> out/pricelist/ (report.md, pricelist.png)"
rm -rf out/pricelist && mkdir -p out/pricelist  # measured afresh; the reference stays cached in out/cache/reference
build/bin/fovea pricelist --scene default --preset fove --quick --cache out/cache --out out/pricelist \
  > out/pricelist/headline.txt
cat out/pricelist/headline.txt

echo "=== 3/3 hello_foveated on the simulated FOVE -> out/hello_foveated.json, out/frames/"
rm -f out/frames/*.png
# Layer config: wait for the tables on the first frame instead of showing the
# app's fallback image while they build; reconstruct where "auto" decides (the
# GPU when the app's Vulkan device is one; on lavapipe, a CPU device, the CPU).
hello() {  # $1: the config's "reconstruction", $2: stats file, rest: hello_foveated arguments
  local reconstruction=$1 stats=$2
  shift 2
  printf '{ "wait_for_tables": true, "log_level": "info", "reconstruction": "%s" }\n' "$reconstruction" \
    > out/foveart_config.json
  FOVEART_CONFIG="$root/out/foveart_config.json" \
  XR_RUNTIME_JSON="$root/build/manifests/foveart_sim_runtime.json" \
  XR_API_LAYER_PATH="$root/build/manifests/explicit" \
  VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
    build/bin/hello_foveated --scene default --interp shepard --k 5 --json "$@" > "$stats"
  jq -r '"reconstruction \"'"$reconstruction"'\" ran on the \(.reconstruction|ascii_upcase): frames traced \(.frames_traced)/\(.frames_submitted), fallbacks \(.views_fallback); layer overhead p50 \(.per_frame.layer_overhead_ms[0].p50|round) ms/eye; gaze age p50 \(.per_frame.gaze_age_ms.p50*10|round/10) ms, p99 \(.per_frame.gaze_age_ms.p99*10|round/10) ms" + (if .reconstruction == "gpu" then "; GPU per eye: gather \(.gpu_stage_ms[0].gather*100|round/100) ms, TAA \(.gpu_stage_ms[0].taa*100|round/100) ms, encode+copy \(.gpu_stage_ms[0].encode*100|round/100) ms" else "" end)' "$stats"
}
FOVEART_SIM_FRAMES=${FOVEART_SIM_FRAMES:-24} FOVEART_SIM_CAPTURE_DIR="$root/out/frames" FOVEART_SIM_CAPTURE_EVERY=8 \
  hello auto out/hello_foveated.json
echo "frames: $(ls out/frames/*.png 2>/dev/null | wc -l) PNGs in out/frames; stats in out/hello_foveated.json"
# The GPU path (shaders/) on the same device, forced: what a headset's GPU runs.
FOVEART_SIM_FRAMES=8 hello gpu out/hello_foveated_gpu.json
