// Depth as the shaders carry it (shaders/common.glsl): metres along the ray,
// no NaN or infinity, since drivers may compile isnan/isinf away.
#pragma once

#include <algorithm>
#include <cmath>

#include "foveation/shader_constants.h"

namespace foveart::layer {

inline constexpr float kDepthUnknown = static_cast<float>(FOVEART_DEPTH_UNKNOWN);  // none returned
inline constexpr float kDepthFar = 3.0e38f;  // the sky: any depth >= FOVEART_DEPTH_FAR is one
static_assert(static_cast<double>(kDepthFar) >= FOVEART_DEPTH_FAR);

inline float shader_depth(float depth_m) {
  if (std::isnan(depth_m) || depth_m < 0.0f) return kDepthUnknown;
  return std::isinf(depth_m) ? kDepthFar : std::min(depth_m, kDepthFar);
}

}  // namespace foveart::layer
