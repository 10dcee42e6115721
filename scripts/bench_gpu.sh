#!/usr/bin/env bash
# Per-eye reconstruction + temporal history on the CPU and the GPU path in one
# run (bench/reconstruction_paths.cpp): a FOVE eye, 1280x1440, nearest and MSM
# k = 5, with each temporal mode ("rays" is the GPU path's default). On a
# machine with a GPU the GPU path runs there (a discrete GPU first); without one
# it runs on lavapipe, a CPU, where only the ratio means anything. Writes
# out/bench/reconstruction_paths.txt with the machine named.
# Usage: scripts/bench_gpu.sh [reconstruction_paths arguments, e.g. --size 640 720 --frames 10]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON -DFOVEART_BUILD_BENCH=ON >/dev/null
cmake --build build -j "$(nproc)" --target reconstruction_paths
mkdir -p out/bench
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
gpus=$(vulkaninfo --summary 2>/dev/null | sed -n 's/^[[:space:]]*deviceName *= *//p' | paste -sd ';' - || true)
{
  echo "machine: $(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB; Vulkan devices: ${gpus:-?}"
  for temporal in rays image; do
    build/bin/reconstruction_paths --interpolation nearest,msm --k 5 --temporal "$temporal" "$@"
  done
} | tee out/bench/reconstruction_paths.txt
