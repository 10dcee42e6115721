// The display transform of foveation/display_transform.cpp, its GPU twin:
// exposure, then a tone-mapping curve, then the clamp to [0, 1].
#ifndef FOVEART_TONE_MAP_GLSL
#define FOVEART_TONE_MAP_GLSL
#extension GL_GOOGLE_include_directive : require
#include "foveation/shader_constants.h"

// Khronos PBR Neutral tone mapping (Khronos 3D Formats WG, 2024).
vec3 tone_map_pbr_neutral(vec3 c) {
  const float start_compression = 0.8 - 0.04;
  const float desaturation = 0.15;
  const float x = min(c.r, min(c.g, c.b));
  const float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
  c -= offset;
  const float peak = max(c.r, max(c.g, c.b));
  if (peak < start_compression) return c;
  const float d = 1.0 - start_compression;
  const float new_peak = 1.0 - d * d / (peak + d - start_compression);
  c *= new_peak / peak;
  const float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
  return mix(c, vec3(new_peak), g);
}

// ACES filmic approximation (Narkowicz 2015), on 0.6 x.
vec3 tone_map_aces(vec3 c) {
  c *= 0.6;
  return (c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14);
}

// NaN and negatives as 0, nothing above the largest half float.
float sanitized(float c) { return c >= 0.0 ? min(c, 65504.0) : 0.0; }

vec3 display_transform(vec3 radiance, float exposure, uint tone_map) {
  vec3 c = radiance * exposure;
  c = vec3(sanitized(c.r), sanitized(c.g), sanitized(c.b));
  if (tone_map == FOVEART_TONE_MAP_PBR_NEUTRAL) c = tone_map_pbr_neutral(c);
  else if (tone_map == FOVEART_TONE_MAP_ACES) c = tone_map_aces(c);
  return clamp(c, 0.0, 1.0);
}

#endif
