#version 450
// The device trace's rays into the render cache (docs/gpu.md "The render
// cache"), after its resolve and fill, in two dispatches:
//   TRACED   the resolve's (one invocation per traced point, device_rays.comp
//            ranked them first in point_rays), over the point's rays: each
//            becomes a new ray of the cache (screen position, depth as depth.h
//            carries it, colour: what the host uploads for a callback's rays);
//            the point's farthest hit, and for a pixel-grid point its pixel's
//            farthest drawn hit, are kept for cache_pixels
//            (foveation::CallbackTrace's farthest_m and
//            foveation::RayHistory::prepare_pixels' drawn_farthest_m, encoded
//            as FOVEART_CACHE_FAR_UNKNOWN says);
//   THINNED  the fill's (one invocation per point content density thinned,
//            ranked after the traced ones): such a point has a colour but no
//            ray of this frame, so it gives cache_pixels no farthest hit (0,
//            as CallbackTrace's -inf), whatever an earlier frame left there.
// A point's rays may be any number (content density's rays by contrast): each
// entry of point_rays says where they begin and how many.
#extension GL_GOOGLE_include_directive : require
#include "gpu/shader_interface/cache_device_rays.h"
#include "gpu/shader_interface/depth.h"

// One point per invocation: the device trace's resolve or fill dispatch reused (device_trace.h).
layout(local_size_x = FOVEART_DEVICE_RESOLVE_GROUP) in;
layout(set = 0, binding = 0, std430) readonly buffer Rays { DeviceRay rays[]; };
layout(set = 0, binding = 1, std430) readonly buffer RayColors { vec4 ray_colors[]; };  // rgb, depth in metres
layout(set = 0, binding = 2, std430) readonly buffer PointRays { DevicePointRays point_rays[]; };
layout(set = 0, binding = 3, std430) readonly buffer Control { uint control[]; };
layout(set = 0, binding = 4, std430) readonly buffer Points { DevicePoint points[]; };
layout(set = 0, binding = 5, std430) writeonly buffer NewRays { NewRay new_rays[]; };
layout(set = 0, binding = 6, std430) writeonly buffer PointFarthest { uint point_farthest[]; };  // per point
layout(set = 0, binding = 7, std430) buffer Drawn { uint drawn[]; };  // per screen pixel

// A ray's depth from its bits (drivers may compile isnan away): a hit at a
// finite distance >= 0, the sky (+inf), or none (NaN, negative, -inf).
bool finite_hit(uint bits) { return bits < 0x7F800000u || bits == 0x80000000u; }

void main() {
  const uint v = gl_GlobalInvocationID.x;
  const uint traced = control[FOVEART_DEVICE_TRACED_POINTS];
  if (pass == FOVEART_CACHE_DEVICE_RAYS_THINNED) {
    if (v >= control[FOVEART_DEVICE_THINNED_POINTS]) return;
    const uint p = point_rays[traced + v].point;
    if (p < point_count) point_farthest[p] = 0u;
    return;
  }
  if (v >= traced) return;
  const DevicePointRays entry = point_rays[v];
  const uint p = entry.point;
  if (p >= point_count) return;
  uint farthest = 0u;
  for (uint s = 0u; s < entry.ray_count; ++s) {
    const uint r = entry.first_ray + s;
    const vec4 c = ray_colors[r];
    const uint bits = floatBitsToUint(c.w);
    const bool hit = finite_hit(bits);
    const float depth = hit ? min(uintBitsToFloat(bits & 0x7FFFFFFFu), FOVEART_DEPTH_SKY)
                            : bits == 0x7F800000u ? FOVEART_DEPTH_SKY : FOVEART_DEPTH_UNKNOWN;
    const vec2 sample_px = vec2(rays[r].origin_sample_x.w, rays[r].direction_sample_y.w);
    new_rays[r] = NewRay(vec4(sample_px, depth, 0.0), vec4(c.rgb, 0.0));
    farthest = max(farthest, hit ? 1u + (bits & 0x7FFFFFFFu) : FOVEART_CACHE_FAR_UNKNOWN);
  }
  point_farthest[p] = farthest;
  const vec4 point = points[p].position_radius_grid;
  if (point.w < 0.5) return;  // a Poisson point's rays are drawn for no pixel
  const ivec2 pixel = ivec2(floor(point.xy - canvas_from_screen_px));
  if (all(greaterThanEqual(pixel, ivec2(0))) && all(lessThan(pixel, screen_px)))
    atomicMax(drawn[pixel.y * screen_px.x + pixel.x], farthest);
}
