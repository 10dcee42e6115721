#!/usr/bin/env bash
# The app-recorded trace's price, the gaze's age: how much earlier than xrEndFrame the rays are
# aimed (XrFoveatedAppTraceStatsFOVEART::acquireToEndFrameMs, per frame). hello_foveated
# --engine gpu --trace-model app through the real loader, the layer and the simulated runtime
# on lavapipe, at the app trace test's setting (320x360 per eye, MSM k = 5, density scale 4,
# 2 rays per point, temporal off), FRAMES frames, RUNS times; the callback model's xrEndFrame
# beside it. Writes DIR/app_trace_gaze_age.md, headed by the commands and this machine.
# Usage: bench/app_trace_gaze_age.sh [DIR [RUNS [FRAMES]]]   (defaults: out/results 4 4);
# needs hello_foveated, the layer and the simulated runtime built
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/results_lib.sh
dir=${1:-out/results}
runs=${2:-4}
frames=${3:-4}
for f in build/bin/hello_foveated build/manifests/foveart_sim_runtime.json; do
  [ -e "$f" ] || { echo "bench/app_trace_gaze_age.sh: $f is missing: build hello_foveated, foveart_layer and foveart_sim_runtime" >&2; exit 2; }
done
mkdir -p "$dir" out/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '{ "wait_for_tables": true, "reconstruction": "gpu" }\n' >"$work/config.json"
hello=(build/bin/hello_foveated --json --engine gpu --eye-size 320 360 --interpolation msm --k 5 --density-scale 4
       --rays-per-point 2 --temporal off --gaze-source none)
load_before=$(results_load)
for run in $(seq 1 "$runs"); do
  for model in app callback; do
    echo "hello_foveated, --trace-model $model: run $run of $runs" >&2
    results_sim_run "$work/config.json" "$frames" "${hello[@]}" --trace-model "$model" \
      >"$work/${model}$run.json" 2>"$work/${model}$run.log" ||
      { echo "bench/app_trace_gaze_age.sh: hello_foveated failed:" >&2; tail -20 "$work/${model}$run.log" >&2; exit 1; }
  done
done
{
  echo "# The app-recorded trace's gaze age"
  echo
  results_machine
  echo "Vulkan device: $(jq -r '.gpu_engine.device' "$work/app1.json"). Load average (1, 5, 15 min): $load_before before," \
       "$(results_load) after. $(results_written_by bench/app_trace_gaze_age.sh "$@")"
  echo
  echo "\`FOVEART_CONFIG={\"wait_for_tables\":true,\"reconstruction\":\"gpu\"} FOVEART_SIM_FRAMES=$frames ${hello[*]}"
  echo "--trace-model app|callback\` through the real loader on the simulated runtime, $runs runs of each."
  echo "Gaze age: \`app_trace.acquire_to_end_frame_ms\`, from the batch's acquire (where its rays are aimed) to"
  echo "\`xrEndFrame\`, per frame: how much older the rays' gaze is than the callback model's, which aims them inside"
  echo "\`xrEndFrame\` (its host wall time, \`per_frame.end_frame_host_ms\`: it records and submits, the frame runs on"
  echo "the device after it). On lavapipe the device is the same CPU cores, so the age is mostly the trace's time: the"
  echo "callback model's device frame (\`per_frame.gpu_frame_ms\`, both eyes' trace and stages) is beside it."
  echo
  echo "| run | frames | gaze age p50 | gaze age p95 | second queue | callback model: xrEndFrame p50 | callback model: device frame p50 |"
  echo "|---|---|---|---|---|---|---|"
  for run in $(seq 1 "$runs"); do
    jq -r --arg run "$run" --slurpfile cb "$work/callback$run.json" '
      def ms: . * 10 | round / 10 | "\(.) ms";
      .app_trace as $a
      | "| \($run) | \($a.acquire_to_end_frame_ms.count) | \($a.acquire_to_end_frame_ms.p50 | ms)"
        + " | \($a.acquire_to_end_frame_ms.p95 | ms) | \($a.second_queue) | \($cb[0].per_frame.end_frame_host_ms.p50 | ms)"
        + " | \($cb[0].per_frame.gpu_frame_ms.p50 | ms) |"' \
      "$work/app$run.json"
  done
} >"$dir/app_trace_gaze_age.md"
echo "wrote $dir/app_trace_gaze_age.md" >&2
