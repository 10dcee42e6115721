#version 450
// The layer's device trace (XR_FOVEART_foveated_ray_tracing.h, traceRaysDevice):
// ray i of rays[0, count) -> colors[i] = (radiance, primary hit distance).
#extension GL_GOOGLE_include_directive : require
#include "trace_core.glsl"

layout(local_size_x = 64) in;

// FoveartDeviceRayCount: the first uint is the valid ray count.
layout(std430, set = 1, binding = 0) readonly buffer RayCount { uint ray_count; };
struct DeviceRay {
  vec4 origin_sample_x;
  vec4 direction_sample_y;
};
layout(std430, set = 1, binding = 1) readonly buffer Rays { DeviceRay rays[]; };
layout(std430, set = 1, binding = 2) writeonly buffer Colors { vec4 colors[]; };

void main() {
  begin_counting();
  const uint i = gl_GlobalInvocationID.x;
  const uint n = min(ray_count, min(uint(rays.length()), uint(colors.length())));
  if (i < n) {
    const DeviceRay r = rays[i];
    uvec3 secondary = uvec3(0u);
    colors[i] = trace_path(r.origin_sample_x.xyz, r.direction_sample_y.xyz, secondary);
    count_rays(1u, secondary);
  }
  end_counting();
}
