#!/usr/bin/env bash
# The README's main job: installs what is missing, builds what it runs, runs FoveaRT
# end to end on built-in defaults and prints a short summary. Everything lands in out/,
# each step's log in out/logs/.
#   1. the FOVE point set: thesis Table 1 counts, picture, curves
#   2. the sample engine's default scene: full versus foveated ray tracing at equal rays
#   3. hello_foveated through the layer on the simulated FOVE headset (real OpenXR loader,
#      Vulkan on lavapipe, 120 Hz simulated gaze): the Embree engine with the CPU
#      reconstruction path, both eyes' frames captured; then the whole frame on the device:
#      the GPU sample engine through the device trace, reconstructed by shaders/
# Usage: scripts/run.sh [--pricelist]
#   --pricelist  also write the quick price list of the default scene to out/pricelist/
#                (the longest step, tens of minutes on 2 cores, its time printed like every
#                step's; docs/lab/pricelist.md has the last list)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
pricelist=0
case "${1:-}" in
  "") ;;
  --pricelist) pricelist=1 ;;
  *) echo "usage: scripts/run.sh [--pricelist]" >&2; exit 2 ;;
esac
SECONDS=0
bash scripts/setup.sh
mkdir -p out/cache out/frames out/logs
export XDG_CACHE_HOME="$root/out/cache"  # the layer caches its tables in $XDG_CACHE_HOME/foveart

step() {  # $1: what, $2: log name, rest: the command; its stdout goes to the log too
  local what=$1 log=out/logs/$2.log
  shift 2
  printf '=== %-58s' "$what"
  local t0=$SECONDS
  if "$@" >"$log" 2>&1; then
    echo " $((SECONDS - t0)) s"
  else
    echo " FAILED"
    tail -20 "$log" >&2
    echo "run.sh: $what failed; the whole log is $log" >&2
    exit 1
  fi
}

# The same tree and flags as `scripts/test.sh --plain`; only the targets this job runs.
step "build (fovea, fovea-eval, hello_foveated, layer, simulated runtime)" build bash -c \
  'cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON &&
   cmake --build build -j "$(nproc)" --target fovea fovea-eval hello_foveated foveart_layer foveart_sim_runtime'

json_to() {  # $1: file for the command's stdout (JSON), rest: the command
  local file=$1
  shift
  "$@" >"$file"
}

step "1/3 FOVE point set -> out/pointset.json" pointset json_to out/pointset.json \
  build/bin/fovea pointset --preset fove --cache-dir out/cache --png out/pointset_centred.png --curves out/curves --json
step "2/3 default scene, full vs foveated -> out/render*" render json_to out/render.json \
  build/bin/fovea render --scene default --preset fove --mode both --interpolation msm --k 5 --frames 5 --cache-dir out/cache \
  --out out/render --json

hello() {  # $1: reconstruction, $2: stats file, rest: hello_foveated arguments
  local reconstruction=$1 stats=$2
  shift 2
  printf '{ "wait_for_tables": true, "log_level": "info", "reconstruction": "%s" }\n' "$reconstruction" \
    >"out/foveart_config_$reconstruction.json"
  FOVEART_CONFIG="$root/out/foveart_config_$reconstruction.json" \
  XR_RUNTIME_JSON="$root/build/manifests/foveart_sim_runtime.json" \
  XR_API_LAYER_PATH="$root/build/manifests/explicit" \
  VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
    json_to "$stats" build/bin/hello_foveated --scene default --interpolation msm --k 5 --json "$@"
}
rm -f out/frames/*.png
FOVEART_SIM_FRAMES=16 FOVEART_SIM_CAPTURE_DIR="$root/out/frames" FOVEART_SIM_CAPTURE_EVERY=8 \
  step "3/3 hello_foveated, CPU path -> out/hello_foveated.json" hello_cpu hello cpu out/hello_foveated.json
FOVEART_SIM_FRAMES=3 \
  step "    hello_foveated, GPU engine -> out/hello_foveated_gpu.json" hello_gpu \
  hello gpu out/hello_foveated_gpu.json --engine gpu
if [ "$pricelist" = 1 ]; then
  rm -rf out/pricelist && mkdir -p out/pricelist
  step "    quick price list -> out/pricelist/" pricelist \
    build/bin/fovea-eval pricelist --scene default --preset fove --quick --cache-dir out/cache --out out/pricelist
fi

# The summary: one plain table, read from the JSON the steps wrote.
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
echo
echo "FoveaRT main job: $((SECONDS / 60)) min $((SECONDS % 60)) s on $(nproc) cores (${cpu:-unknown CPU}), Vulkan on lavapipe"
jq -rn --slurpfile p out/pointset.json --slurpfile r out/render.json \
  --slurpfile c out/hello_foveated.json --slurpfile g out/hello_foveated_gpu.json --arg pricelist "$pricelist" '
  def r1: . * 10 | round / 10;
  def r2: . * 100 | round / 100;
  def group: tostring | until(test("^[0-9]{1,3}(,|$)"); sub("(?<a>[0-9])(?<b>[0-9]{3})(?<c>,|$)"; "\(.a),\(.b)\(.c)"));
  def row(a; b): "| \(a) | \(b) |";
  ($r[0].rings | map(select(.from_deg == 0))[0]) as $fovea
  | row("what"; "value"), "|---|---|",
    row("points per eye, FOVE \($p[0].width)x\($p[0].height), centred gaze";
        "\($p[0].on_screen_centred | group) of \($p[0].pixels | group) pixels (\($p[0].fraction_centred * 100 | r1) %)"),
    row("speedup at equal rays, default scene, MSM k = 5";
        "\($r[0].speedup | r2)x (its content allows \($r[0].content_speedup | r2)x; the trace alone \($r[0].speedup_parts.trace_speedup | r2)x, plus \($r[0].speedup_parts.fixed_ms | r1) ms of reconstruction)"),
    row("fovea (0-2.5 deg): foveated against the full render at equal rays";
        if $fovea.psnr == null then "identical: the pixel-exact fovea traces the full render'"'"'s own rays"
        else "PSNR \($fovea.psnr | r1) dB" end),
    row("layer time per eye, CPU path (p50, callback excluded)";
        "\($c[0].per_frame.layer_overhead_ms[0].p50 | r1) ms, temporal \"\($c[0].temporal)\""),
    ($g[0].gpu_stage_ms[0]) as $stage
    | row("whole frame per eye on the device, GPU engine, lavapipe (a CPU device)";
        "trace \($g[0].per_frame.gpu_trace_ms[0].p50 | r1) ms (p50) + reconstruction \($stage.gather + $stage.temporal + $stage.encode | r1) ms, temporal \"\($g[0].temporal)\""),
    ($g[0].per_frame) as $pf
    | row("GPU engine: GPU time per eye (p50, left / right) beside the host time per frame in xrEndFrame";
        "GPU \($pf.gpu_eye_ms[0].p50 | r1) / \($pf.gpu_eye_ms[1].p50 | r1) ms per eye; host in xrEndFrame \($pf.end_frame_host_ms.p50 | r1) ms p50, \($pf.end_frame_host_ms.p95 | r1) ms p95 per frame"),
    row("pictures"; "out/render_full.png, out/render_foveated.png, out/frames/, out/pointset_centred.png"),
    row("price list (accuracy per ring against a converged reference)";
        if $pricelist == "1" then "out/pricelist/report.md" else "docs/lab/pricelist.md (scripts/run.sh --pricelist: out/pricelist/)" end)'
