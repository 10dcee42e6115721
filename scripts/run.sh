#!/usr/bin/env bash
# The README's main job: installs what is missing, builds, and runs the most
# complete FoveaRT pipeline on built-in defaults. Output goes to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
echo "=== FOVE point set: picture, curves and statistics -> out/"
build/bin/fovea pointset --preset fove --cache out/cache --png out/pointset_centred.png \
  --curves out/curves --json | tee out/pointset.json
