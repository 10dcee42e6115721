#!/usr/bin/env bash
# Installs every Debian 12 package FoveaRT builds, tests or runs with.
# Idempotent: packages already present are skipped; works as root or through sudo.
# Prints one line; apt's own output goes to out/logs/setup.log (its tail on a failure).
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # foveation core
  libglm-dev libeigen3-dev libnanoflann-dev libxxhash-dev
  # tools: CLI parsing, JSON, images, plots
  libcli11-dev nlohmann-json3-dev libstb-dev libplplot-dev plplot-driver-cairo
  # sample engine
  libembree-dev libtinygltf-dev assimp-testmodels
  # gaze provider
  libhidapi-dev libusb-1.0-0-dev umockdev libumockdev-dev
  # Vulkan on the CPU (lavapipe) and shader compiler
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools glslang-dev spirv-tools
  # OpenXR SDK 1.0.20: loader, headers, hello_xr, core validation layer
  libopenxr-dev libopenxr-loader1 libopenxr-utils openxr-layer-corevalidation
  # tests and benchmarks; jq prints the main job's summary lines; universal-ctags
  # measures function lengths (scripts/check_function_length.sh)
  libgtest-dev libgmock-dev libbenchmark-dev jq universal-ctags
  # fuzzing (scripts/fuzz.sh): clang and its libFuzzer / sanitizer runtimes
  clang libclang-rt-14-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: missing packages (${missing[*]}) and not root, no sudo" >&2; exit 1
  fi
fi
log_dir="$(cd "$(dirname "$0")/.." && pwd)/out/logs"
mkdir -p "$log_dir"
log="$log_dir/setup.log"
printf 'setup: installing %d packages (%s) ...' "${#missing[@]}" "${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
SECONDS=0
if { $SUDO apt-get update -q && $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"; } >"$log" 2>&1; then
  echo " done in ${SECONDS} s (log: out/logs/setup.log)"
else
  echo " FAILED after ${SECONDS} s" >&2
  tail -20 "$log" >&2
  echo "setup: apt-get failed; the whole log is $log" >&2
  exit 1
fi
