#version 450
// Stages 1-2 of a frame traced on the device (docs/gpu.md "The device
// trace"): foveation::CallbackTrace's visible test, content density and
// foveation::PointRays on the GPU. A point whose screen position lies in the
// screen and its margin is visible; with content density (device_density.glsl)
// a visible point of a level finer than its tile's (the eye's tiles of the
// last frame's contrast) whose nearest parent is visible is thinned (no rays:
// the resolve fills it from its parents), and a traced point casts its rays by
// its disc and its tile's contrast; else every visible point casts
// rays_per_point. The rays are compacted in the point set's order, so a frame
// gives the same rays in the same places on every run (and neighbouring rays
// stay neighbours, as the set's Hilbert order made them):
//   COUNT  a workgroup per block of points sums its points' rays, traced
//          points and thinned points;
//   SCAN   one workgroup: each of the blocks' sums becomes where the block's
//          rays, traced and thinned points begin (scan.glsl); the totals are
//          the ray and point counts; the indirect dispatches follow: the
//          engine's over the rays, the resolve's over the traced points and
//          the fill's over the thinned ones;
//   WRITE  a workgroup per block: each point's first ray and rank are its
//          block's starts plus those of the points before it in the block (a
//          scan in shared memory); its rays go there (pixel-grid points
//          jittered over their pixel, the rest in their disc, thesis 4.2), each
//          with its footprint: the point's disc radius as an angle at the eye;
//          a visible point's (point, first ray, count) goes to point_rays at
//          its rank (traced points first, then thinned), for the resolve.
#extension GL_GOOGLE_include_directive : require
#include "eye_rays.glsl"
#include "jitter.glsl"
#include "gpu/shader_interface/device_rays.h"
#include "gpu/shader_interface/ray_dispatch.h"
#include "device_density.glsl"

layout(local_size_x = FOVEART_DEVICE_RAYS_BLOCK) in;
layout(set = 0, binding = 0, std430) readonly buffer Points { DevicePoint points[]; };
// Per ray: (origin xyz, sample x), (direction xyz, sample y): the engine's contract.
layout(set = 0, binding = 1, std430) writeonly buffer Rays { DeviceRay rays[]; };
layout(set = 0, binding = 2, std430) writeonly buffer PointIndex { uint point_index[]; };
// XrFoveatedDeviceRayCountFOVEART, the resolve's and fill's dispatches and the point counts (device_trace.h).
layout(set = 0, binding = 3, std430) buffer Control { uint control[]; };
// Three regions of a word per block of points (BLOCK_RAYS, _TRACED, _THINNED):
// its rays, traced and thinned points (COUNT), then where they begin (SCAN).
layout(set = 0, binding = 4, std430) buffer Blocks { uint block_first[]; };
// Per ray: its footprint in radians (XrFoveatedDeviceRayFootprintFOVEART).
layout(set = 0, binding = 5, std430) writeonly buffer Footprints { float footprint_rad[]; };
// Per point: its level and parents (content density; else unread).
layout(set = 0, binding = 6, std430) readonly buffer Levels { DeviceLevel levels[]; };
// The eye's tiles: the last frame's contrast and level per tile (device_trace.h).
layout(set = 0, binding = 7, std430) readonly buffer Tiles { uint tile_words[]; };
// Per rank of a visible point: its rays (device_trace.h), traced points first.
layout(set = 0, binding = 8, std430) writeonly buffer PointRays { DevicePointRays point_rays[]; };

#define SCAN_ARRAY block_first
#define SCAN_THREADS FOVEART_DEVICE_RAYS_BLOCK
#include "scan.glsl"

// The regions of block_first: a word per block each.
#define BLOCK_RAYS 0u
#define BLOCK_TRACED 1u
#define BLOCK_THINNED 2u

// Per invocation: the rays, traced and thinned points of the block before its point.
shared uvec3 block_before[FOVEART_DEVICE_RAYS_BLOCK];

// The control words from the totals: the counts and the indirect dispatches.
void write_counts(uint count, uint traced, uint thinned) {
  control[FOVEART_DEVICE_VISIBLE_POINTS] = traced + thinned;
  control[FOVEART_DEVICE_TRACED_POINTS] = traced;
  control[FOVEART_DEVICE_THINNED_POINTS] = thinned;
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
  const uint group = uint(FOVEART_DEVICE_RESOLVE_GROUP);
  control[FOVEART_DEVICE_RESOLVE_DISPATCH] = (traced + group - 1u) / group;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH + 1u] = 1u;
  control[FOVEART_DEVICE_RESOLVE_DISPATCH + 2u] = 1u;
  control[FOVEART_DEVICE_FILL_DISPATCH] = (thinned + group - 1u) / group;
  control[FOVEART_DEVICE_FILL_DISPATCH + 1u] = 1u;
  control[FOVEART_DEVICE_FILL_DISPATCH + 2u] = 1u;
}

bool visible_point(uint i, out vec2 screen) {
  screen = vec2(0.0);
  if (i >= point_count) return false;
  screen = points[i].position_radius_grid.xy - canvas_from_screen_px;
  return screen.x >= -margin_px && screen.x < float(screen_px.x) + margin_px && screen.y >= -margin_px &&
         screen.y < float(screen_px.y) + margin_px;
}

// The rays, traced and thinned points of the block's points before this
// invocation's (exclusive, in gl_LocalInvocationIndex order: a Hillis-Steele
// scan in shared memory), and (*block_sums) of all of them.
uvec3 before_in_block(uvec3 own, out uvec3 block_sums) {
  const uint t = gl_LocalInvocationIndex;
  block_before[t] = own;
  barrier();
  for (uint step = 1u; step < uint(FOVEART_DEVICE_RAYS_BLOCK); step <<= 1u) {
    const uvec3 add = t >= step ? block_before[t - step] : uvec3(0u);
    barrier();
    block_before[t] += add;
    barrier();
  }
  block_sums = block_before[FOVEART_DEVICE_RAYS_BLOCK - 1];
  return block_before[t] - own;
}

// Content density's rays of visible point i at `screen` (0: thinned), from the
// eye's tiles of the last frame: CallbackTrace::thins and PointRays::rays_of.
uint density_rays(uint i, vec2 screen) {
  const uvec2 tiles = density_tiles(screen_px, tile_px);
  const bool measured = (flags & FOVEART_DEVICE_RAYS_MEASURED) != 0u &&
                        tile_words[FOVEART_DEVICE_TILES_MEASURED] == 1u && tile_words[FOVEART_DEVICE_TILES_X] == tiles.x &&
                        tile_words[FOVEART_DEVICE_TILES_Y] == tiles.y && tile_words[FOVEART_DEVICE_TILES_PX] == tile_px;
  float contrast = DENSITY_INFINITY;  // none measured: every point traced, rays by its disc
  if (measured) {
    const uint t = density_tile_of(screen, screen_px, tile_px);
    contrast = uintBitsToFloat(tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_CONTRAST, t)]);
    const uint parent = levels[i].parents_level.x;
    vec2 parent_screen;
    if ((flags & FOVEART_DEVICE_RAYS_THIN) != 0u &&
        levels[i].parents_level.w > tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_LEVEL, t)] &&
        parent != FOVEART_DEVICE_NO_PARENT && visible_point(parent, parent_screen)) {
      return 0u;
    }
  }
  const vec4 p = points[i].position_radius_grid;
  if ((flags & FOVEART_DEVICE_RAYS_VARY) == 0u || p.w > 1.5) return rays_per_point;  // the fovea keeps all
  return density_ray_count(rays_per_point, p.z, contrast,
                           density_rays_contrast_at(p.xy - canvas_centre_px, rays_contrast, rays_step_distance_sq_px2));
}

// Point i's rays this frame: 0 when invisible (*visible false) or thinned.
uint rays_of(uint i, out bool visible, out vec2 screen) {
  visible = visible_point(i, screen);
  if (!visible) return 0u;
  return (flags & (FOVEART_DEVICE_RAYS_THIN | FOVEART_DEVICE_RAYS_VARY)) != 0u ? density_rays(i, screen)
                                                                                : rays_per_point;
}

// The angle at the eye between the point's centre and the edge of its disc (radius r_i, thesis eq. 4):
// 2 asin(|d1 - d0| / 2) of the two unit directions, exact for small angles too.
float disc_radius_rad(vec2 screen, float radius_px) {
  const vec3 d0 = eye_ray_direction(tan_lrud, orientation, vec2(screen_px), screen);
  const vec3 d1 = eye_ray_direction(tan_lrud, orientation, vec2(screen_px), screen + vec2(radius_px, 0.0));
  return 2.0 * asin(min(0.5 * length(d1 - d0), 1.0));
}

void write_rays(uint i, uint first, uint count, vec2 screen) {
  const vec4 p = points[i].position_radius_grid;
  const bool bspline2 = (flags & FOVEART_DEVICE_RAYS_BSPLINE2) != 0u;
  const float footprint = disc_radius_rad(screen, p.z);
  for (uint s = 0u; s < count; ++s) {
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

// WRITE: visible point i's entry at its rank, and its rays; `before`: the
// block's rays, traced and thinned points before it.
void write_point(uint i, uint blocks, uint rays, uvec3 before, vec2 screen) {
  const uint b = gl_WorkGroupID.x;
  if (rays == 0u) {  // thinned: after every traced point
    const uint rank = control[FOVEART_DEVICE_TRACED_POINTS] + block_first[BLOCK_THINNED * blocks + b] + before.z;
    point_rays[rank] = DevicePointRays(i, FOVEART_DEVICE_THINNED, 0u);
    return;
  }
  const uint first = block_first[BLOCK_RAYS * blocks + b] + before.x;
  point_rays[block_first[BLOCK_TRACED * blocks + b] + before.y] = DevicePointRays(i, first, rays);
  write_rays(i, first, rays, screen);
}

void main() {
  const uint blocks = (point_count + uint(FOVEART_DEVICE_RAYS_BLOCK) - 1u) / uint(FOVEART_DEVICE_RAYS_BLOCK);
  if (pass == FOVEART_DEVICE_RAYS_SCAN) {
    const uint count = scan_all(BLOCK_RAYS * blocks, blocks);
    const uint traced = scan_all(BLOCK_TRACED * blocks, blocks);
    const uint thinned = scan_all(BLOCK_THINNED * blocks, blocks);
    if (gl_LocalInvocationIndex == 0u) write_counts(count, traced, thinned);
    return;
  }
  const uint i = gl_GlobalInvocationID.x;
  bool visible;
  vec2 screen;
  const uint rays = rays_of(i, visible, screen);
  const uvec3 own = uvec3(rays, visible && rays > 0u ? 1u : 0u, visible && rays == 0u ? 1u : 0u);
  uvec3 block_sums;
  const uvec3 before = before_in_block(own, block_sums);
  if (pass == FOVEART_DEVICE_RAYS_COUNT) {
    if (gl_LocalInvocationIndex == 0u) {
      for (uint region = BLOCK_RAYS; region <= BLOCK_THINNED; ++region)
        block_first[region * blocks + gl_WorkGroupID.x] = block_sums[region];
    }
    return;
  }
  if (visible) write_point(i, blocks, rays, before, screen);
}
