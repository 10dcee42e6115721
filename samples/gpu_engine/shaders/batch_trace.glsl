// The layer's device trace (XR_FOVEART_foveated_ray_tracing.h, traceRaysDevice)
// for one ray: ray i of rays[0, count) -> colors[i] = (radiance, primary hit
// distance). Set 1: the batch's buffers. Shared by trace.comp (compute) and
// trace.rgen (ray-tracing pipeline); include trace_core.glsl first.
#ifndef FOVEART_GPU_BATCH_TRACE_GLSL
#define FOVEART_GPU_BATCH_TRACE_GLSL

// XrFoveatedDeviceRayCountFOVEART: the first uint is the valid ray count.
layout(std430, set = 1, binding = 0) readonly buffer RayCount { uint ray_count; };
struct DeviceRay {
  vec4 origin_sample_x;
  vec4 direction_sample_y;
};
layout(std430, set = 1, binding = 1) readonly buffer Rays { DeviceRay rays[]; };
layout(std430, set = 1, binding = 2) writeonly buffer Colors { vec4 colors[]; };
// XrFoveatedDeviceRayFootprintFOVEART's buffer: radians per ray (the engine binds zeros when the batch has none).
layout(std430, set = 1, binding = 3) readonly buffer Footprints { float footprints[]; };

// The valid rays: the count, within what the buffers hold.
uint batch_ray_count() { return min(ray_count, min(uint(rays.length()), uint(colors.length()))); }

// Traces ray i when it is one of the valid rays; counts it.
void trace_batch_ray(uint i) {
  const uint n = batch_ray_count();
  if (i < n) {
    const DeviceRay r = rays[i];
    ray_footprint_rad = i < uint(footprints.length()) ? footprints[i] : 0.0;
    uvec3 secondary = uvec3(0u);
    colors[i] = trace_path(r.origin_sample_x.xyz, r.direction_sample_y.xyz, secondary);
    count_rays(1u, secondary);
  }
}

#endif
