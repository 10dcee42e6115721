#version 450
// The frame's traced colours into their points' slots (the slots were cleared
// to "not traced" before): foveation::point_colors_from_list on the GPU.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = 64) in;
#include "gpu/shader_interface/scatter.h"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  const uvec4 e = uploaded[i];
  if (e.x >= point_count) return;
  colors[e.x] = vec4(uintBitsToFloat(e.yzw), 1.0);
  point_depth[e.x] = uintBitsToFloat(uploaded[count + i / 4u][i % 4u]);
}
