#!/usr/bin/env bash
# The layer's CPU path per eye, as the main job runs it: hello_foveated through the
# layer on the simulated FOVE headset (Embree engine, CPU reconstruction, MSM k = 5,
# 16 frames), RUNS times, and the encode benchmark that compares the per-pixel display
# transform with the run-based encode in one process. Writes RESULTS/cpu_path.md,
# headed by the commands and this machine. Run it on an idle machine: the load average
# before and after is written beside the numbers.
# Usage: scripts/bench_cpu_path.sh [results-dir [runs]]   (defaults: out/results, 3)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
results=${1:-out/results}
runs=${2:-3}
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON -DFOVEART_BUILD_BENCH=ON >/dev/null
cmake --build build -j "$(nproc)" --target hello_foveated foveart_layer foveart_sim_runtime layer_bench >/dev/null
mkdir -p "$results" out/bench out/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '{ "wait_for_tables": true, "reconstruction": "cpu" }\n' >"$work/config.json"

load_before=$(results_load)
hello=(build/bin/hello_foveated --scene default --interpolation msm --k 5 --json)
for run in $(seq 1 "$runs"); do
  echo "hello_foveated, CPU path: run $run of $runs" >&2
  results_sim_run "$work/config.json" 16 "${hello[@]}" >"$work/run$run.json" 2>"$work/run$run.log"
done
echo "layer_bench BM_EncodeRgba8" >&2
encode_args=(--benchmark_filter=BM_EncodeRgba8 --benchmark_out="out/bench/encode_rgba8.json"
             --benchmark_out_format=json)
build/bin/layer_bench "${encode_args[@]}" >/dev/null
load_after=$(results_load)

{
  echo "# The layer's CPU path per eye"
  echo
  results_written_by scripts/bench_cpu_path.sh "$@"
  results_machine
  echo "Load average (1, 5, 15 min): $load_before before, $load_after after."
  echo
  echo "## Layer time per eye in \`xrEndFrame\`, callback excluded"
  echo
  echo "\`FOVEART_CONFIG={\"wait_for_tables\":true,\"reconstruction\":\"cpu\"} FOVEART_SIM_FRAMES=16" \
       "${hello[*]}\` through the real loader on the simulated runtime, $runs runs."
  echo
  echo "| run | temporal | left eye p50 | right eye p50 | left eye p99 | right eye p99 |"
  echo "|---|---|---|---|---|---|"
  for run in $(seq 1 "$runs"); do
    jq -r --arg run "$run" '.per_frame.layer_overhead_ms as $o
      | "| \($run) | \(.temporal) | \($o[0].p50 * 10 | round / 10) ms | \($o[1].p50 * 10 | round / 10) ms"
        + " | \($o[0].p99 * 10 | round / 10) ms | \($o[1].p99 * 10 | round / 10) ms |"' "$work/run$run.json"
  done
  echo
  echo "The p99 holds the first frame, which builds the view's tables."
  echo
  echo "## The encode into the swapchain's RGBA8 sRGB bytes, one FOVE eye (1280x1440)"
  echo
  echo "\`build/bin/layer_bench ${encode_args[*]}\`: the per-pixel display transform against"
  echo "\`encode_rgba8\` over runs of pixels, both on the executor's workers, in one process."
  echo
  echo "| variant | wall per eye |"
  echo "|---|---|"
  jq -r '.benchmarks[] | "| \(.label) | \(.real_time * 10 | round / 10) ms |"' out/bench/encode_rgba8.json
} >"$results/cpu_path.md"
echo "wrote $results/cpu_path.md"
