// The render cache on the GPU (docs/gpu.md "The render cache"): the twin of
// foveation::RayCache as FoveatedView runs it. Its own descriptor set; the
// host side is gpu/ray_cache.hpp. A frame (after, with a device trace,
// cache_device_rays and cache_pixels: the new rays and the pixels):
//   cache_count  (begin) the kept and new rays' counts, the dispatch for them
//   cache_rays   every kept ray projected into this view and depth-tested,
//                every new ray anchored; each within reach counted into its
//                cell of a 2-px grid (its slot there from the atomic count)
//   cache_scan   the counts become where each cell's rays begin
//   cache_bin    each ray into its cell's place; the ones to keep appended
//                to the other anchor buffer, one frame older
//   cache_filter each pixel: sum(w L) / sum(w) over the rays within its
//                filter, widened to its footprint; the gather where none is
//   cache_count  (end) a faulted device trace keeps nothing
// Sums run in whatever order the atomics gave: results agree with the CPU
// within float rounding, not bit for bit.
#ifndef FOVEART_RAY_CACHE_GLSL
#define FOVEART_RAY_CACHE_GLSL

#extension GL_GOOGLE_include_directive : require
#include "quat.glsl"

#include "foveation/shader_constants.h"
#include "gpu/shader_interface/depth.h"
#include "gpu/shader_interface/cache_push.h"
#define CELL_PX float(FOVEART_RAY_CACHE_CELL_PX)
#define KEPT_RAY_OCCLUSION_TOLERANCE FOVEART_KEPT_RAY_OCCLUSION_TOLERANCE
#define DEPTH_FAR FOVEART_DEPTH_FAR
#define SCAN_BLOCK FOVEART_RAY_CACHE_SCAN_BLOCK  // cells per workgroup of cache_scan

// The gather of this frame (rgb, depth); cache_filter writes the frame into it.
layout(set = 0, binding = 0, std430) buffer Current { vec4 current[]; };
layout(set = 0, binding = 1, std430) buffer AnchorsIn { Anchor anchors_in[]; };  // kept, then this frame's new ones
layout(set = 0, binding = 2, std430) writeonly buffer AnchorsOut { Anchor anchors_out[]; };
layout(set = 0, binding = 3, std430) readonly buffer NewRays { NewRay new_rays[]; };
layout(set = 0, binding = 4, std430) buffer Rays { RayFrame ray_frame[]; };
// Per cell its count, then where its rays begin; [cell_count] the total;
// from [cell_count + 1] cache_scan's block sums.
layout(set = 0, binding = 5, std430) coherent buffer Cells { uint cells[]; };
layout(set = 0, binding = 6, std430) buffer ByCell { CellRay by_cell[]; };
// Per screen pixel: x its filter's footprint (1: the pixel filter), y the
// distance beyond which a kept ray there is covered (< 0: cannot tell).
layout(set = 0, binding = 7, std430) readonly buffer Pixels { vec2 pixels[]; };
// The count words (FOVEART_CACHE_*): kept, added, kept_out, the indirect dispatch.
layout(set = 0, binding = 8, std430) coherent buffer Counts { uint counts[]; };
// With a device trace (FOVEART_CACHE_DEVICE_RAYS): its control words (the
// rays it made) and its resolve's status (a fault); else the counts again.
layout(set = 0, binding = 9, std430) readonly buffer DeviceControl { uint device_control[]; };
layout(set = 0, binding = 10, std430) readonly buffer DeviceStatus { uint device_status[]; };


// foveation::eye_ray_direction: the unit tracking-space direction through a screen position.
vec3 eye_ray_direction(vec2 sample_px) {
  const vec2 s = sample_px / vec2(size_px);
  const vec3 v = vec3(tan_lrud.x + s.x * (tan_lrud.y - tan_lrud.x), tan_lrud.z + s.y * (tan_lrud.w - tan_lrud.z), -1.0);
  return normalize(rotate(orientation, v));
}

// foveation::project_direction: where a direction crosses the screen; false at or behind the eye plane.
bool project_direction(vec3 direction, out vec2 sample_px) {
  const vec3 d = rotate(conjugate(orientation), direction);
  sample_px = vec2(0.0);
  if (!(d.z < 0.0)) return false;
  const vec2 t = d.xy / -d.z;
  sample_px = vec2((t.x - tan_lrud.x) / (tan_lrud.y - tan_lrud.x) * float(size_px.x),
                   (t.y - tan_lrud.z) / (tan_lrud.w - tan_lrud.z) * float(size_px.y));
  return true;
}

// foveation::RayCache::row_within_reach: within the filter's reach of the image.
bool within_reach(vec2 q) {
  const float r = filter_kind == FOVEART_RAY_CACHE_FILTER_BOX ? 0.0 : 1.0;
  return q.x >= -r && q.x < float(size_px.x) + r && q.y >= -r && q.y < float(size_px.y) + r;
}

// foveation::pixel_filter_weight, per axis.
float pixel_filter_weight(float offset_px) {
  if (filter_kind == FOVEART_RAY_CACHE_FILTER_BOX) return offset_px >= -0.5 && offset_px < 0.5 ? 1.0 : 0.0;
  const float u = abs(offset_px);
  if (u < 0.5) return 0.75 - u * u;
  if (u < 1.5) return 0.5 * (1.5 - u) * (1.5 - u);
  return 0.0;
}

// The per-ray and per-cell passes' workgroup size, and their grid-stride
// loops: a dispatch of at most 65535 workgroups covers any count.
#define GROUP_SIZE FOVEART_RAY_CACHE_GROUP_SIZE
uint stride() { return gl_NumWorkGroups.x * uint(GROUP_SIZE); }

#endif
