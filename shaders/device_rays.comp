#version 450
// Stages 1-2 of a frame traced on the device (docs/gpu.md "The device
// trace"): foveation::CallbackTrace's visible test and foveation::PointRays
// on the GPU. Mode 0, one invocation per point of the set: a point whose
// screen position lies in the screen and its margin takes the next rank and
// writes its rays_per_point rays at rank * spp (pixel-grid points jittered
// over their pixel, the rest in their disc, thesis 4.2). Mode 1, one
// invocation: the ray count and the indirect dispatches from the ranks taken.
#extension GL_GOOGLE_include_directive : require
#include "eye_rays.glsl"
#include "jitter.glsl"
#include "foveation/shader_constants.h"

layout(local_size_x = 64) in;
// Per point: canvas x, y (pixels), disc radius (pixels), 1 = on the pixel grid.
layout(set = 0, binding = 0, std430) readonly buffer Points { vec4 points[]; };
// Per ray: (origin xyz, sample x), (direction xyz, sample y): the engine's contract.
layout(set = 0, binding = 1, std430) writeonly buffer Rays { vec4 rays[]; };
layout(set = 0, binding = 2, std430) writeonly buffer PointIndex { uint point_index[]; };
// FoveartDeviceRayCount, then the resolve's dispatch and the visible points (shader_constants.h).
layout(set = 0, binding = 3, std430) buffer Control { uint control[]; };

layout(push_constant) uniform Push {
  vec4 tan_lrud;         // the frustum: tan of the left, right, up, down angles
  vec4 orientation;      // unit quaternion xyzw, tracking from view
  vec4 position_m;       // xyz
  ivec2 screen_px;
  vec2 canvas_from_screen_px;
  float margin_px;
  uint rays_per_point;
  uint point_count;
  uint flags;            // bit 0: bspline2 pixel filter; bit 1: mode 1 (counts)
  uvec2 seed;            // low, high word
};

void write_counts() {
  const uint visible = control[FOVEART_DEVICE_VISIBLE_POINTS];
  const uint count = visible * rays_per_point;
  control[0] = count;
  control[1] = (count + 63u) / 64u;
  control[2] = 1u;
  control[3] = 1u;
  control[4] = count;
  control[5] = 1u;
  control[6] = 1u;
  control[7] = 0u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH] = (visible + 63u) / 64u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH + 1u] = 1u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH + 2u] = 1u;
}

void main() {
  if ((flags & 2u) != 0u) {
    if (gl_GlobalInvocationID.x == 0u) write_counts();
    return;
  }
  const uint i = gl_GlobalInvocationID.x;
  if (i >= point_count) return;
  const vec4 p = points[i];
  const vec2 screen = p.xy - canvas_from_screen_px;
  if (!(screen.x >= -margin_px && screen.x < float(screen_px.x) + margin_px && screen.y >= -margin_px &&
        screen.y < float(screen_px.y) + margin_px)) {
    return;
  }
  const uint first = atomicAdd(control[FOVEART_DEVICE_VISIBLE_POINTS], 1u) * rays_per_point;
  const bool bspline2 = (flags & 1u) != 0u;
  for (uint s = 0u; s < rays_per_point; ++s) {
    const vec2 sample_px = p.w > 0.5 ? pixel_sample_px(screen, s, seed, screen_px.x, bspline2)
                                     : screen + unit_disc_sample(seed, i, s) * p.z;
    const uint r = first + s;
    rays[2u * r] = vec4(position_m.xyz, sample_px.x);
    rays[2u * r + 1u] = vec4(eye_ray_direction(tan_lrud, orientation, vec2(screen_px), sample_px), sample_px.y);
    point_index[r] = i;
  }
}
