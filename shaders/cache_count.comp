#version 450
// The render cache's counts on the device (ray_cache.glsl), so that no
// count crosses to the host and frames can be in flight together:
//   BEGIN  this frame's kept rays (the last frame's appended ones, none on a
//          restart; at most what the buffers hold beside the new rays) and
//          new rays (the callback's from the host, a device trace's from its
//          control words), and cache_rays' and cache_bin's indirect dispatch;
//   END    a device trace whose resolve found a fault (NaN, infinite or
//          negative colours) keeps nothing: the next frame starts anew, as
//          the CPU's history does after a failed frame.
#extension GL_GOOGLE_include_directive : require
#include "ray_cache.glsl"
#include "gpu/shader_interface/device_trace.h"

layout(local_size_x = 1) in;

void main() {
  const bool device = (flags & FOVEART_CACHE_DEVICE_RAYS) != 0u;
  if (phase == FOVEART_CACHE_COUNT_END) {
    const bool fault = device && device_status[FOVEART_DEVICE_STATUS_INVALID_COMPONENTS] != 0u;
    counts[FOVEART_CACHE_KEPT_OUT] = fault ? 0u : min(counts[FOVEART_CACHE_KEPT_OUT], capacity);
    return;
  }
  const uint new_rays = min(device ? device_control[0] : added, capacity);
  const bool restart = (flags & FOVEART_CACHE_RESTART) != 0u;
  const uint kept = restart ? 0u : min(counts[FOVEART_CACHE_KEPT_OUT], capacity - new_rays);
  counts[FOVEART_CACHE_KEPT] = kept;
  counts[FOVEART_CACHE_ADDED] = new_rays;
  counts[FOVEART_CACHE_KEPT_OUT] = 0u;
  const uint groups = (kept + new_rays + uint(GROUP_SIZE) - 1u) / uint(GROUP_SIZE);
  counts[FOVEART_CACHE_DISPATCH] = clamp(groups, 1u, 65535u);  // the passes loop beyond (stride())
  counts[FOVEART_CACHE_DISPATCH + 1u] = 1u;
  counts[FOVEART_CACHE_DISPATCH + 2u] = 1u;
}
