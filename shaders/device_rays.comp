#version 450
// Stages 1-2 of a frame traced on the device (docs/gpu.md "The device
// trace"): foveation::CallbackTrace's visible test and foveation::PointRays
// on the GPU. A point whose screen position lies in the screen and its margin
// is visible; the visible points are compacted in the point set's order, so a
// frame gives the same rays in the same places on every run (and neighbouring
// rays stay neighbours, as the set's Hilbert order made them):
//   COUNT  a workgroup per block of points counts its visible ones
//          (subgroup ballots, then the subgroups' counts in shared memory);
//   SCAN   one workgroup: the blocks' counts become where each block's points
//          begin (scan.glsl), the total is the visible points; the ray count
//          and the indirect dispatches follow;
//   WRITE  a workgroup per block: each visible point's rank is its block's
//          start plus the visible points before it in the block; its
//          rays_per_point rays go at rank * spp (pixel-grid points jittered
//          over their pixel, the rest in their disc, thesis 4.2), each with
//          its footprint: the point's disc radius as an angle at the eye.
// Ranks follow gl_LocalInvocationIndex when subgroups hold consecutive
// invocations (gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID), as
// the drivers lay them out; tests/gpu/device_trace_test.cpp checks the order.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "eye_rays.glsl"
#include "jitter.glsl"
#include "gpu/shader_interface/device_rays.h"
#include "gpu/shader_interface/ray_dispatch.h"

layout(local_size_x = FOVEART_DEVICE_RAYS_BLOCK) in;
layout(set = 0, binding = 0, std430) readonly buffer Points { DevicePoint points[]; };
// Per ray: (origin xyz, sample x), (direction xyz, sample y): the engine's contract.
layout(set = 0, binding = 1, std430) writeonly buffer Rays { DeviceRay rays[]; };
layout(set = 0, binding = 2, std430) writeonly buffer PointIndex { uint point_index[]; };
// XrFoveatedDeviceRayCountFOVEART, then the resolve's dispatch and the visible points (device_trace.h).
layout(set = 0, binding = 3, std430) buffer Control { uint control[]; };
// Per block of points: its visible points (COUNT), then where they begin (SCAN).
layout(set = 0, binding = 4, std430) buffer Blocks { uint block_first[]; };
// Per ray: its footprint in radians (XrFoveatedDeviceRayFootprintFOVEART).
layout(set = 0, binding = 5, std430) writeonly buffer Footprints { float footprint_rad[]; };

#define SCAN_ARRAY block_first
#define SCAN_THREADS FOVEART_DEVICE_RAYS_BLOCK
#include "scan.glsl"

shared uint subgroup_before[FOVEART_DEVICE_RAYS_BLOCK];  // per subgroup: visible points before it in the block

void write_counts() {
  const uint visible = control[FOVEART_DEVICE_VISIBLE_POINTS];
  const uint count = visible * rays_per_point;
  control[0] = count;
  uint groups_x, rows;
  ray_dispatch_groups(count, groups_x, rows);  // two-dimensional: every side within Vulkan's minimum limit
  control[1] = groups_x;
  control[2] = rows;
  control[3] = 1u;
  uint width, height;
  trace_rays_size(count, width, height);  // rows, within Vulkan's minimum ray-tracing limits
  control[4] = width;
  control[5] = height;
  control[6] = 1u;
  control[7] = 0u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH] = (visible + 63u) / 64u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH + 1u] = 1u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH + 2u] = 1u;
}

bool visible_point(uint i, out vec2 screen) {
  screen = vec2(0.0);
  if (i >= point_count) return false;
  screen = points[i].position_radius_grid.xy - canvas_from_screen_px;
  return screen.x >= -margin_px && screen.x < float(screen_px.x) + margin_px && screen.y >= -margin_px &&
         screen.y < float(screen_px.y) + margin_px;
}

// The visible points of this workgroup's block before this invocation's, and (*block_visible) in all of it.
uint rank_in_block(bool visible, out uint block_visible) {
  const uvec4 ballot = subgroupBallot(visible);
  if (subgroupElect()) subgroup_before[gl_SubgroupID] = subgroupBallotBitCount(ballot);
  barrier();
  uint before = 0u;
  block_visible = 0u;
  for (uint s = 0u; s < gl_NumSubgroups; ++s) {
    const uint n = subgroup_before[s];
    before += s < gl_SubgroupID ? n : 0u;
    block_visible += n;
  }
  return before + subgroupBallotExclusiveBitCount(ballot);
}

// The angle at the eye between the point's centre and the edge of its disc (radius r_i, thesis eq. 4):
// 2 asin(|d1 - d0| / 2) of the two unit directions, exact for small angles too.
float disc_radius_rad(vec2 screen, float radius_px) {
  const vec3 d0 = eye_ray_direction(tan_lrud, orientation, vec2(screen_px), screen);
  const vec3 d1 = eye_ray_direction(tan_lrud, orientation, vec2(screen_px), screen + vec2(radius_px, 0.0));
  return 2.0 * asin(min(0.5 * length(d1 - d0), 1.0));
}

void write_rays(uint i, uint rank, vec2 screen) {
  const vec4 p = points[i].position_radius_grid;
  const uint first = rank * rays_per_point;
  const bool bspline2 = (flags & FOVEART_DEVICE_RAYS_BSPLINE2) != 0u;
  const float footprint = disc_radius_rad(screen, p.z);
  for (uint s = 0u; s < rays_per_point; ++s) {
    const vec2 sample_px = p.w > 0.5 ? pixel_sample_px(screen, s, seed, screen_px.x, bspline2)
                                     : screen + unit_disc_sample(seed, i, s) * p.z;
    const uint r = first + s;
    rays[r].origin_sample_x = vec4(position_m.xyz, sample_px.x);
    rays[r].direction_sample_y =
        vec4(eye_ray_direction(tan_lrud, orientation, vec2(screen_px), sample_px), sample_px.y);
    point_index[r] = i;
    footprint_rad[r] = footprint;
  }
}

void main() {
  const uint blocks = (point_count + uint(FOVEART_DEVICE_RAYS_BLOCK) - 1u) / uint(FOVEART_DEVICE_RAYS_BLOCK);
  if (pass == FOVEART_DEVICE_RAYS_SCAN) {
    const uint visible = scan_all(0u, blocks);
    if (gl_LocalInvocationIndex == 0u) {
      control[FOVEART_DEVICE_VISIBLE_POINTS] = visible;
      write_counts();
    }
    return;
  }
  const uint i = gl_GlobalInvocationID.x;
  vec2 screen;
  const bool visible = visible_point(i, screen);
  uint block_visible;
  const uint rank = rank_in_block(visible, block_visible);
  if (pass == FOVEART_DEVICE_RAYS_COUNT) {
    if (gl_LocalInvocationIndex == 0u) block_first[gl_WorkGroupID.x] = block_visible;
  } else if (visible) {
    write_rays(i, block_first[gl_WorkGroupID.x] + rank, screen);
  }
}
