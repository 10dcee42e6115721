#!/usr/bin/env bash
# The GPU benchmark, in one run on one Vulkan device (a discrete or integrated
# GPU first, else lavapipe, a CPU, where only the ratios mean anything):
#  1. bench/gpu_frame.cpp: one FOVE eye (1280x1440) of the default scene on
#     the GPU sample engine: the full render (the fair baseline) and the
#     foveated frame through the layer's device path, per stage (trace,
#     reconstruction, temporal history, encode), with the speedup;
#  2. bench/reconstruction_paths.cpp: reconstruction + history per eye on the
#     CPU and the GPU path.
# Writes out/bench/gpu_frame.json and docs/results/bench_gpu_<device>.md,
# headed by the command and the machine.
#
# Usage:
#   scripts/bench_gpu.sh [--frames N]            set up, build and run here
#   scripts/bench_gpu.sh --bundle FILE.tar.xz    build here, pack the programs and the
#                                                libraries they need (not glibc, not the
#                                                Vulkan loader) for a machine without them
#   scripts/bench_gpu.sh --from-bundle FILE.tar.xz [--frames N]
#                                                run a bundle: no set-up, no build (a fresh
#                                                GPU machine with only a driver and a loader)
set -euo pipefail
cd "$(dirname "$0")/.."
mode=run bundle="" frames=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --bundle) mode=bundle bundle=$2; shift 2 ;;
    --from-bundle) mode=from-bundle bundle=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    *) echo "bench_gpu.sh: unknown argument '$1' (see the usage at the top of the script)" >&2; exit 2 ;;
  esac
done

bin=build/bin
if [[ $mode != from-bundle ]]; then
  bash scripts/setup.sh
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON -DFOVEART_BUILD_BENCH=ON >/dev/null
  cmake --build build -j "$(nproc)" --target gpu_frame reconstruction_paths
fi
if [[ $mode == bundle ]]; then
  stage=$(mktemp -d)
  mkdir -p "$stage/bin" "$stage/lib"
  cp "$bin/gpu_frame" "$bin/reconstruction_paths" "$stage/bin/"
  # Every library the programs load, except the C and C++ runtimes and the Vulkan loader
  # (the machine's own: a newer libstdc++ serves these programs, and its GPU driver needs it).
  ldd "$bin/gpu_frame" "$bin/reconstruction_paths" | awk '/=> \//{print $3}' | sort -u |
    grep -Ev '/(libc|libm|libpthread|libdl|librt|ld-linux[^/]*|libvulkan|libstdc\+\+|libgcc_s)\.so' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  tar -C "$stage" -cJf "$bundle" bin lib
  rm -rf "$stage"
  echo "bench_gpu.sh: wrote $bundle ($(du -h "$bundle" | cut -f1)); run it with scripts/bench_gpu.sh --from-bundle $bundle"
  exit 0
fi
if [[ $mode == from-bundle ]]; then
  unpacked=$(mktemp -d)
  tar -C "$unpacked" -xJf "$bundle"
  bin=$unpacked/bin
  export LD_LIBRARY_PATH="$unpacked/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
fi

cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
machine="$(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB, load average $(cut -d' ' -f1 /proc/loadavg) at the start"
mkdir -p out/bench docs/results
json=out/bench/gpu_frame.json
args=(--json "$json")  # gpu_frame times 8 frames on a GPU, 2 on lavapipe (tens of seconds a FOVE eye)
[[ -n $frames ]] && args+=(--frames "$frames")
echo "machine: $machine"
frame_table=$("$bin/gpu_frame" "${args[@]}" | tee /dev/stderr)
device=$(sed -n 's/.*"device": "\(.*\)",*/\1/p' "$json" | head -1)

# Reconstruction + history on the CPU and the GPU path.
recon_args=(--interpolation nearest,msm --k 5)
grep -q '"device_is_cpu": true' "$json" && recon_args+=(--frames 3)
recon_table=$(for temporal in rays image; do
  "$bin/reconstruction_paths" "${recon_args[@]}" --temporal "$temporal"
done | tee /dev/stderr)

slug=$(echo "$device" | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\+/_/g; s/^_//; s/_$//' | cut -c1-40)
result=docs/results/bench_gpu_${slug:-device}.md
{
  echo "# The GPU benchmark on ${device:-a Vulkan device}"
  echo
  echo "Written by \`scripts/bench_gpu.sh${frames:+ --frames $frames}\` on $(date -u +%F). Machine: $machine."
  echo
  echo "## One FOVE eye, full and foveated, on the GPU sample engine (bench/gpu_frame.cpp)"
  echo
  echo "GPU timestamps, medians over the timed frames. The full frame's history and encode are the foveated"
  echo "frame's passes on the same pixels; \"trace\" of the foveated frame is the device's rays, the engine's"
  echo "trace and the resolve. Speedup: full / foveated per frame pair, median."
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
echo "wrote $result and $json"
