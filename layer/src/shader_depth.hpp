// Depth as the shaders carry it (shaders/common.glsl): metres along the ray,
// no NaN or infinity, since drivers may compile isnan/isinf away.
#pragma once

#include <algorithm>
#include <cmath>

namespace foveart::layer {

inline constexpr float kDepthUnknown = -1.0f;  // none returned
inline constexpr float kDepthFar = 3.0e38f;    // >= DEPTH_FAR (1e30): the sky

inline float shader_depth(float depth_m) {
  if (std::isnan(depth_m) || depth_m < 0.0f) return kDepthUnknown;
  return std::isinf(depth_m) ? kDepthFar : std::min(depth_m, kDepthFar);
}

}  // namespace foveart::layer
