// How the layer samples a view when neither the app nor the config says
// otherwise. Header-only, so an app that renders its own full frames beside the
// layer's foveated ones (hello_foveated --mode full) traces the same rays.
#pragma once

#include <cstdint>

namespace foveart::layer {

// The point set's seed, and the ray jitter's seed of a frame without temporal
// history: a static gaze then gives what `fovea render --mode foveated` gives.
inline constexpr std::uint64_t kSampleSeed = 1;

// The config's default "rays_per_point" (docs/layer.md).
inline constexpr std::uint32_t kDefaultRaysPerPoint = 1;

}  // namespace foveart::layer
