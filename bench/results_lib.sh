# Sourced by the scripts that write results files (docs/results/): the lines that head them, and
# an app run through the real loader, the layer and the simulated runtime on lavapipe.

# "Written by `COMMAND ARGS`." with the arguments quoted as given.
results_written_by() {
  local command=$1
  shift
  echo "Written by \`$command$([ $# -gt 0 ] && printf ' %q' "$@")\`."
}

# This machine in one line: cores, CPU, memory, OS, compiler, build type and the date.
results_machine() {
  local cpu
  cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
  echo "Machine: $(nproc) cores, ${cpu:-unknown CPU}, $(free -g | awk '/Mem:/{print $2}') GiB," \
       "$(. /etc/os-release; echo "$PRETTY_NAME"), $(g++ --version | head -1), RelWithDebInfo; $(date -u +%Y-%m-%d)."
}

# Exits 2 with "SCRIPT: BINARY is missing" unless each BINARY is built (an executable file).
results_need() {
  local script=$1 binary
  shift
  for binary in "$@"; do
    [ -x "$binary" ] || { echo "$script: $binary is missing: build first (scripts/run.sh)" >&2; exit 2; }
  done
}

# The load average (1, 5, 15 min) now.
results_load() {
  cut -d' ' -f1-3 /proc/loadavg
}

# Runs COMMAND ARGS through the loader on the simulated runtime (the build's manifests, lavapipe)
# with the layer config CONFIG and FRAMES frames; layer caches under out/cache.
results_sim_run() {
  local config=$1 frames=$2
  shift 2
  FOVEART_CONFIG="$config" XDG_CACHE_HOME="$PWD/out/cache" FOVEART_SIM_FRAMES="$frames" \
  XR_RUNTIME_JSON="$PWD/build/manifests/foveart_sim_runtime.json" \
  XR_API_LAYER_PATH="$PWD/build/manifests/explicit" \
  VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
    "$@"
}
