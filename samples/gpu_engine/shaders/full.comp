#version 450
// The full render on the compute tracer: one invocation per pixel, 8 x 8 per
// workgroup (full_render.glsl).
#extension GL_GOOGLE_include_directive : require
#include "trace_core.glsl"
#include "full_render.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  begin_counting();
  render_pixel(gl_GlobalInvocationID.xy);
  end_counting();
}
