#!/usr/bin/env bash
# Installs every Debian 12 package FoveaRT builds, tests or runs with.
# Idempotent: packages already present are skipped; works as root or through sudo.
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
  # tests and benchmarks; jq prints the main job's summary lines
  libgtest-dev libgmock-dev libbenchmark-dev jq
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
echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
