// Depth as the shaders carry it (gpu/shader_interface/depth.h): metres along
// the ray, no NaN or infinity, since drivers may compile isnan/isinf away.
#pragma once

#include <algorithm>
#include <cmath>

#include "gpu/shader_interface/depth.h"

namespace foveart::gpu {

inline constexpr float kDepthUnknown = static_cast<float>(FOVEART_DEPTH_UNKNOWN);  // none returned
// The sky: any depth >= FOVEART_DEPTH_FAR is one.
inline constexpr float kDepthFar = static_cast<float>(FOVEART_DEPTH_SKY);
static_assert(FOVEART_DEPTH_SKY >= FOVEART_DEPTH_FAR);

inline float shader_depth(float depth_m) {
  if (std::isnan(depth_m) || depth_m < 0.0f) return kDepthUnknown;
  return std::isinf(depth_m) ? kDepthFar : std::min(depth_m, kDepthFar);
}

}  // namespace foveart::gpu
