// shaders/cache_device_rays.comp's push constants (gpu/ray_cache.cpp).
#ifndef FOVEART_SHADER_INTERFACE_CACHE_DEVICE_RAYS_H
#define FOVEART_SHADER_INTERFACE_CACHE_DEVICE_RAYS_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/device_trace.h"
#include "gpu/shader_interface/ray_cache.h"  // the cache's structs and constants (no push constants)

FOVEART_SHADER_INTERFACE_BEGIN

// cache_device_rays.comp's two dispatches (CacheDeviceRaysPush::pass).
#define FOVEART_CACHE_DEVICE_RAYS_TRACED 0u   // a traced point each: its rays into the cache
#define FOVEART_CACHE_DEVICE_RAYS_THINNED 1u  // a thinned point each: no new ray of its own

// cache_device_rays.comp: the device trace's rays as new rays of the cache.
FOVEART_PUSH_CONSTANTS(CacheDeviceRaysPush) {
  ivec2 screen_px;
  vec2 canvas_from_screen_px;
  uint pass;  // FOVEART_CACHE_DEVICE_RAYS_*
  uint point_count;
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_CACHE_DEVICE_RAYS_H
