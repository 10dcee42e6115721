#!/usr/bin/env bash
# Runs every benchmark program in build/bin (*_bench): Google Benchmark JSON to
# out/bench/<name>.json, then `fovea-eval bench-md` turns each into
# RESULTS/<name>.md, headed by the exact command that measured it and this
# machine (CPU, cores, OS, compiler, build type). Benchmarks are never part of
# the test suite.
# Usage: scripts/bench.sh [filter-regex [results-dir]]   (results-dir default: out/results)
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-.}
results=${2:-out/results}
bash scripts/setup.sh
# The same tree and flags as scripts/run.sh and `scripts/test.sh --plain`: the
# numbers in docs/ come from these binaries, and switching the build type
# back and forth would rebuild everything each time.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON -DFOVEART_BUILD_BENCH=ON >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out/bench "$results"
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
cpu=${cpu:-unknown CPU}
echo "machine: $(nproc) cores, $cpu, $(free -g | awk '/Mem:/{print $2}') GiB"
for b in build/bin/*_bench; do
  name=$(basename "$b")
  echo "=== $name"
  args=(--benchmark_filter="$filter" --benchmark_out="out/bench/$name.json" --benchmark_out_format=json
        --benchmark_context=cores="$(nproc)",cpu="${cpu//,/}")  # key=value pairs split at commas
  "$b" "${args[@]}"
  build/bin/fovea-eval bench-md --json "out/bench/$name.json" --title "$name" --out "$results/$name.md" \
    --command "$b $(printf '%q ' "${args[@]}" | sed 's/ $//')"
  echo "wrote $results/$name.md"
done
