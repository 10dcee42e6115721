#!/usr/bin/env bash
# Runs every benchmark program in build/bin (*_bench) and writes Google
# Benchmark JSON to out/bench/<name>.json, with the machine named in each
# file's context. Benchmarks are never part of the test suite.
# Usage: scripts/bench.sh [filter-regex]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# The same tree and flags as scripts/run.sh and `scripts/test.sh --plain`: the
# numbers in docs/ come from these binaries, and switching the build type
# back and forth would rebuild everything each time.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON -DFOVEART_BUILD_BENCH=ON >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out/bench
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
cpu=${cpu:-unknown CPU}
echo "machine: $(nproc) cores, $cpu, $(free -g | awk '/Mem:/{print $2}') GiB"
for b in build/bin/*_bench; do
  name=$(basename "$b")
  echo "=== $name"
  "$b" --benchmark_filter="${1:-.}" --benchmark_out="out/bench/$name.json" --benchmark_out_format=json \
       --benchmark_context=cores="$(nproc)",cpu="${cpu//,/}"  # key=value pairs split at commas
done
