// The push constants of the render cache's passes over its own buffers
// (shaders/ray_cache.glsl: cache_rays, cache_scan, cache_bin, cache_filter,
// cache_count; gpu/ray_cache.cpp).
#ifndef FOVEART_SHADER_INTERFACE_CACHE_PUSH_H
#define FOVEART_SHADER_INTERFACE_CACHE_PUSH_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/ray_cache.h"

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(CachePush) {
  vec4 orientation;  // the eye's, x y z w
  vec4 position_m;   // the eye's, xyz
  vec4 tan_lrud;     // tan(left, right, up, down)
  ivec2 size_px;
  ivec2 cells_xy;
  uint flags;        // FOVEART_CACHE_*
  uint added;        // this frame's new rays (the callback's; a device trace's are counted on the device)
  uint filter_kind;  // FOVEART_RAY_CACHE_FILTER_*
  uint max_age;      // frames a ray is kept (0: no limit)
  uint phase;        // FOVEART_SCAN_* or FOVEART_CACHE_COUNT_*
  uint cell_count;
  uint capacity;     // anchors either buffer holds
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_CACHE_PUSH_H
