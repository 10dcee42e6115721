#version 450
// Linear radiance -> display values (tone_map.glsl) -> RGBA8 texels for the
// swapchain: sRGB-encoded (IEC 61966-2-1) for an sRGB format, else
// [0,1] -> [0,255]; alpha 255. NaN encodes as 0. A faulted frame
// (common.glsl frame_faulted) writes nothing: the last good frame stays shown.
// The GPU twin of foveation::encode_rgba8 (within one 8-bit step: pow).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tone_map.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
#include "gpu/shader_interface/encode.h"

uint encode_channel(float c) {
  if (!(c > 0.0)) return 0u;
  if (c >= 1.0) return 255u;
  if (srgb == 0u) return uint(floor(c * 255.0 + 0.5));
  const float e = c <= 0.0031308 ? c * 12.92 : 1.055 * pow(c, 1.0 / 2.4) - 0.055;  // IEC 61966-2-1
  return uint(floor(e * 255.0 + 0.5));
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size_px.x || p.y >= size_px.y || frame_faulted()) return;
  const uint i = uint(p.y * size_px.x + p.x);
  const vec3 c = display_transform(history_out[i].rgb, exposure, tone_map);
  encoded[i] = encode_channel(c.r) | (encode_channel(c.g) << 8) | (encode_channel(c.b) << 16) | (255u << 24);
}
