#!/usr/bin/env bash
# The GPU benchmark, in one run on one Vulkan device (a discrete or integrated
# GPU first, else lavapipe, a CPU, where only the ratios mean anything):
#  1. bench/gpu_frame.cpp: one FOVE eye (1280x1440) of the default scene on
#     the GPU sample engine: the full render (the fair baseline) and the
#     foveated frame through the layer's device path, per stage (trace,
#     reconstruction, temporal history, encode), with the speedup; it fails,
#     naming the device, where the queue has no timestamps or they read 0;
#  2. the whole frame, both eyes, with the copy into the swapchain: hello_foveated
#     --engine gpu through the real OpenXR loader, the layer and the simulated
#     runtime at the FOVE eye size, twice: a timing run (the layer's GPU time per
#     eye and stage, the app's host time in xrEndFrame) and a counting run under
#     the Vulkan layer VK_LAYER_FOVEART_count with the engine's work counters on
#     (dispatches, barriers, submissions per frame; rays of each kind, BVH nodes
#     per ray); bench/frame_report.cpp prints it, with the bytes each stage binds,
#     "fits"/"misses" for 3.5 ms and 7 ms per eye, and a predicted time per eye
#     from --bandwidth-gbs and --rays-per-s (n/a without them, and on a CPU); the
#     timing run's content density (the GPU path's default): its passes' GPU time
#     per eye beside the trace, and its rays beside a third run's with content
#     density off (layer config "content_contrast": 0);
#  3. bench/reconstruction_paths.cpp: reconstruction + history per eye on the
#     CPU and the GPU path.
# Writes out/bench/ (the JSON and the counts) and docs/results/bench_gpu_<device>.md,
# headed by the command and the machine.
#
# Usage:
#   scripts/bench_gpu.sh [OPTIONS]                 set up, build and run here
#   scripts/bench_gpu.sh --bundle FILE.tar.xz      build here, pack the programs, the OpenXR
#                                                  layer, the simulated runtime, the counting
#                                                  Vulkan layer, their manifests and the
#                                                  libraries they need (not glibc, not the
#                                                  Vulkan loader) for a machine without them
#   scripts/bench_gpu.sh --from-bundle FILE.tar.xz [OPTIONS]
#                                                  run a bundle: no set-up, no build (a fresh
#                                                  GPU machine with only a driver and a loader)
# OPTIONS: --frames N (gpu_frame's timed frames), --hello-frames N (hello_foveated's
#          timing run, default 5: the layer reports a frame's GPU times up to two frames
#          later; the counting run one more), --bandwidth-gbs X and
#          --rays-per-s Y (the device's memory bandwidth and the engine's ray rate,
#          for the prediction)
set -euo pipefail
cd "$(dirname "$0")/.."
mode=run bundle="" frames="" hello_frames=5 bandwidth="" ray_rate=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --bundle) mode=bundle bundle=$2; shift 2 ;;
    --from-bundle) mode=from-bundle bundle=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --hello-frames) hello_frames=$2; shift 2 ;;
    --bandwidth-gbs) bandwidth=$2; shift 2 ;;
    --rays-per-s) ray_rate=$2; shift 2 ;;
    *) echo "bench_gpu.sh: unknown argument '$1' (see the usage at the top of the script)" >&2; exit 2 ;;
  esac
done
SECONDS=0
programs=(gpu_frame reconstruction_paths gpu_frame_report hello_foveated)
# Where the programs, libraries and manifests are: the build tree, or an unpacked bundle.
bin=build/bin lib=build/lib
runtime_json=$PWD/build/manifests/foveart_sim_runtime.json
xr_layer_dir=$PWD/build/manifests/explicit
vk_layer_dir=$PWD/build/tests/vk_count/layer
if [[ $mode != from-bundle ]]; then
  bash scripts/setup.sh
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON -DFOVEART_BUILD_BENCH=ON >/dev/null
  cmake --build build -j "$(nproc)" --target "${programs[@]}" foveart_layer foveart_sim_runtime foveart_vk_count_layer
fi

# A manifest naming its library relative to itself ($1 manifest, $2 library path relative to it).
relocate_manifest() {
  sed -i "s|\"library_path\": *\"[^\"]*\"|\"library_path\": \"$2\"|" "$1"
}

if [[ $mode == bundle ]]; then
  stage=$(mktemp -d)
  mkdir -p "$stage/bin" "$stage/lib" "$stage/manifests/explicit" "$stage/vk_layer"
  for p in "${programs[@]}"; do cp "$bin/$p" "$stage/bin/"; done
  modules=("$lib/libXrApiLayer_foveart.so" "$lib/libfoveart_sim_runtime.so" "$vk_layer_dir/libVkLayer_foveart_count.so")
  cp "${modules[@]}" "$stage/lib/"
  cp "$runtime_json" "$stage/manifests/foveart_sim_runtime.json"
  relocate_manifest "$stage/manifests/foveart_sim_runtime.json" ../lib/libfoveart_sim_runtime.so
  cp "$xr_layer_dir"/XR_APILAYER_FOVEART_foveated_ray_tracing.json "$stage/manifests/explicit/"
  relocate_manifest "$stage/manifests/explicit/XR_APILAYER_FOVEART_foveated_ray_tracing.json" ../../lib/libXrApiLayer_foveart.so
  cp "$vk_layer_dir/VkLayer_foveart_count.json" "$stage/vk_layer/"
  relocate_manifest "$stage/vk_layer/VkLayer_foveart_count.json" ../lib/libVkLayer_foveart_count.so
  # Every library the programs and modules load, except the C and C++ runtimes and the Vulkan
  # loader (the machine's own: a newer libstdc++ serves these programs, and its GPU driver needs it).
  ldd "${programs[@]/#/$bin/}" "${modules[@]}" | awk '/=> \//{print $3}' | sort -u |
    grep -Ev '/(libc|libm|libpthread|libdl|librt|ld-linux[^/]*|libvulkan|libstdc\+\+|libgcc_s)\.so' |
    while read -r l; do cp -L "$l" "$stage/lib/"; done
  tar -C "$stage" -cJf "$bundle" bin lib manifests vk_layer
  rm -rf "$stage"
  echo "bench_gpu.sh: wrote $bundle ($(du -h "$bundle" | cut -f1)); run it with scripts/bench_gpu.sh --from-bundle $bundle"
  exit 0
fi
if [[ $mode == from-bundle ]]; then
  unpacked=$(mktemp -d)
  tar -C "$unpacked" -xJf "$bundle"
  bin=$unpacked/bin
  runtime_json=$unpacked/manifests/foveart_sim_runtime.json
  xr_layer_dir=$unpacked/manifests/explicit
  vk_layer_dir=$unpacked/vk_layer
  export LD_LIBRARY_PATH="$unpacked/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
fi

cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
machine="$(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB, load average $(cut -d' ' -f1 /proc/loadavg) at the start"
mkdir -p out/bench docs/results
json=out/bench/gpu_frame.json
args=(--json "$json")  # gpu_frame times 8 frames on a GPU, 2 on lavapipe (tens of seconds a FOVE eye)
[[ -n $frames ]] && args+=(--frames "$frames")
echo "machine: $machine"
frame_table=$("$bin/gpu_frame" "${args[@]}" | tee /dev/stderr) ||
  { echo "bench_gpu.sh: gpu_frame failed (its message above names the device); no results written" >&2; exit 1; }
device=$(sed -n 's/.*"device": "\(.*\)",*/\1/p' "$json" | head -1)

# The whole frame, both eyes: hello_foveated through the loader, the layer and the simulated runtime.
hello() {  # $1: JSON out, $2: frames, rest: extra arguments; the environment adds the counting layer
  local out=$1 n=$2  # $config_extra: more layer config keys
  shift 2
  printf '{ "wait_for_tables": true, "log_level": "warn", "reconstruction": "gpu"%s }\n' "${config_extra:-}" \
    >out/bench/foveart_config.json
  FOVEART_CONFIG=$PWD/out/bench/foveart_config.json XDG_CACHE_HOME=$PWD/out/bench/cache \
  FOVEART_SIM_FRAMES=$n XR_RUNTIME_JSON=$runtime_json XR_API_LAYER_PATH=$xr_layer_dir \
    "$bin/hello_foveated" --engine gpu --scene default --eye-size 1280 1440 --interpolation msm --k 5 \
    --temporal image --json "$@" >"$out" 2>"${out%.json}.log" ||
    { echo "bench_gpu.sh: hello_foveated failed; its log is ${out%.json}.log" >&2; tail -5 "${out%.json}.log" >&2; exit 1; }
}
hello out/bench/hello_timing.json "$hello_frames"
rm -f out/bench/vk_counts.jsonl
VK_LAYER_PATH=$vk_layer_dir VK_INSTANCE_LAYERS=VK_LAYER_FOVEART_count FOVEART_VK_COUNT_OUT=$PWD/out/bench/vk_counts.jsonl \
  hello out/bench/hello_counting.json $((hello_frames + 1)) --count-work  # a steady frame after the start
config_extra=', "content_contrast": 0' hello out/bench/hello_eccentricity_only.json "$hello_frames"
report_args=(--timing out/bench/hello_timing.json --counting out/bench/hello_counting.json
  --vk-counts out/bench/vk_counts.jsonl --program hello_foveated --frame-json "$json"
  --eccentricity-only out/bench/hello_eccentricity_only.json)
[[ -n $bandwidth ]] && report_args+=(--bandwidth-gbs "$bandwidth")
[[ -n $ray_rate ]] && report_args+=(--rays-per-s "$ray_rate")
whole_table=$("$bin/gpu_frame_report" "${report_args[@]}" | tee /dev/stderr) ||
  { echo "bench_gpu.sh: the whole frame's GPU times read 0 on ${device:-the device}; no results written" >&2; exit 1; }

# Reconstruction + history on the CPU and the GPU path.
recon_args=(--interpolation nearest,msm --k 5)
grep -q '"device_is_cpu": true' "$json" && recon_args+=(--frames 3)
recon_table=$(for temporal in rays image; do
  "$bin/reconstruction_paths" "${recon_args[@]}" --temporal "$temporal"
done | tee /dev/stderr)

command="scripts/bench_gpu.sh${frames:+ --frames $frames}"
[[ $hello_frames != 5 ]] && command+=" --hello-frames $hello_frames"
command+="${bandwidth:+ --bandwidth-gbs $bandwidth}${ray_rate:+ --rays-per-s $ray_rate}"
slug=$(echo "$device" | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\+/_/g; s/^_//; s/_$//' | cut -c1-40)
result=docs/results/bench_gpu_${slug:-device}.md
{
  echo "# The GPU benchmark on ${device:-a Vulkan device}"
  echo
  echo "Written by \`$command\` on $(date -u +%F) in $((SECONDS / 60)) min $((SECONDS % 60)) s. Machine: $machine."
  echo
  echo "## The whole frame, both eyes, through the layer (hello_foveated --engine gpu, bench/frame_report.cpp)"
  echo
  echo "The real OpenXR loader, the layer and the simulated runtime, FOVE eyes (1280x1440), $hello_frames frames. GPU"
  echo "times are the layer's timestamps per eye, read with its stats (of the newest finished frame: the frame is"
  echo "pipelined): trace (device rays, the engine's trace, resolve) and the eye as p50 over the frames with times"
  echo "but the first, the reconstruction stages of the last reading, encode with the copy into the swapchain."
  echo "The host time is the app's steady clock around each xrEndFrame call. Work, rays and nodes come from a"
  echo "second run under VK_LAYER_FOVEART_count with the engine's work counters on; bytes are the sizes of the"
  echo "buffers each stage binds, an upper bound on the bytes it touches. Content density (on by default on the GPU"
  echo "path): the timing run's fill and contrast passes per eye beside its trace, and its rays beside a third run's,"
  echo "the timing run's with layer config \`\"content_contrast\": 0\` (eccentricity only)."
  echo
  echo '```'
  echo "$whole_table"
  echo '```'
  echo
  echo "## One FOVE eye, full and foveated, on the GPU sample engine (bench/gpu_frame.cpp)"
  echo
  echo "GPU timestamps, medians over the timed frames. The full frame's history and encode are the foveated"
  echo "frame's passes on the same pixels; \"trace\" of the foveated frame is the device's rays, the engine's"
  echo "trace and the resolve. Speedup: full / foveated per frame pair, median. No copy into an image here."
  echo
  echo '```'
  echo "$frame_table"
  echo '```'
  echo
  echo "## Reconstruction and history per eye, CPU and GPU path (bench/reconstruction_paths.cpp)"
  echo
  echo '```'
  echo "$recon_table"
  echo '```'
} > "$result"
echo "wrote $result and out/bench/ in $((SECONDS / 60)) min $((SECONDS % 60)) s"
