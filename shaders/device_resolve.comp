#version 450
// Stage 3's end on the device: each visible point's colour is the mean of
// its rays' colours and its depth the nearest of their hits, as
// foveation::CallbackTrace makes them on the CPU, written into the point
// slots the gather reads. NaN, infinite and negative colour components are
// counted into the status the host reads after the frame (the view then
// falls back); NaN is found from the bits (drivers may compile isnan away).
#extension GL_GOOGLE_include_directive : require
#include "gpu/shader_interface/depth.h"
#include "gpu/shader_interface/device_resolve.h"

layout(local_size_x = 64) in;
layout(set = 0, binding = 0, std430) readonly buffer RayColors { vec4 ray_colors[]; };  // rgb, depth in metres
layout(set = 0, binding = 1, std430) readonly buffer PointIndex { uint point_index[]; };
layout(set = 0, binding = 2, std430) readonly buffer Control { uint control[]; };
layout(set = 0, binding = 3, std430) buffer Status { uint status[]; };  // invalid components, visible points
layout(set = 0, binding = 4, std430) writeonly buffer Colors { vec4 colors[]; };
layout(set = 0, binding = 5, std430) writeonly buffer PointDepth { float point_depth[]; };

bool not_finite(uint bits) { return (bits & 0x7F800000u) == 0x7F800000u; }
bool invalid(uint bits) { return not_finite(bits) || (bits > 0x80000000u); }  // NaN, infinite, below -0

void main() {
  const uint visible = control[FOVEART_DEVICE_VISIBLE_POINTS];
  const uint v = gl_GlobalInvocationID.x;
  if (v == 0u) status[FOVEART_DEVICE_STATUS_VISIBLE_POINTS] = visible;
  if (v >= visible) return;
  const uint first = v * rays_per_point;
  const uint p = point_index[first];
  if (p >= point_count) return;
  vec3 sum = vec3(0.0);
  uint bad = 0u;
  float nearest_m = FOVEART_DEPTH_UNKNOWN;
  for (uint s = 0u; s < rays_per_point; ++s) {
    const vec4 c = ray_colors[first + s];
    const uvec3 bits = floatBitsToUint(c.rgb);
    bad += (invalid(bits.r) ? 1u : 0u) + (invalid(bits.g) ? 1u : 0u) + (invalid(bits.b) ? 1u : 0u);
    sum += c.rgb;
    const uint depth_bits = floatBitsToUint(c.w);
    if (depth_bits == 0x7F800000u) {  // +inf: the sky
      if (nearest_m == FOVEART_DEPTH_UNKNOWN) nearest_m = FOVEART_DEPTH_SKY;
    } else if (!not_finite(depth_bits) && depth_bits < 0x80000000u) {  // finite and >= 0
      nearest_m = nearest_m == FOVEART_DEPTH_UNKNOWN ? c.w : min(nearest_m, c.w);
    }
  }
  if (bad != 0u) atomicAdd(status[FOVEART_DEVICE_STATUS_INVALID_COMPONENTS], bad);
  colors[p] = vec4(sum / float(rays_per_point), 1.0);
  point_depth[p] = nearest_m;
}
