#version 450
// Stage 3's end on the device, three dispatches (DeviceResolvePush::pass):
//   POINTS    a traced point each (indirect: device_rays.comp's SCAN sized it
//             by the traced points, which its WRITE ranked first in
//             point_rays): a traced point's colour is the mean of its rays'
//             colours and its depth the nearest of their hits, as
//             foveation::CallbackTrace makes them on the CPU, written into the
//             point slots the gather reads. NaN, infinite and negative colour
//             components are counted into the status the host reads after the
//             frame (the view then falls back); NaN is found from the bits
//             (drivers may compile isnan away). With content density its
//             display-linear luminance goes into its tile's range (atomic
//             min/max of the ordered bits of a non-negative float);
//   FILL      a thinned point each (indirect, ranked after the traced ones): it takes the weighted colour of its
//             traced parents and the nearest traced parent's depth
//             (CallbackTrace::fill_point), so the gather reads a complete set;
//   CONTRAST  a tile each: the contrast of its 3x3 neighbourhood's range and
//             its level, which the next frame's device_rays.comp reads (the
//             eye's tiles); the header says whether they hold (no fault).
#extension GL_GOOGLE_include_directive : require
#include "gpu/shader_interface/depth.h"
#include "gpu/shader_interface/device_resolve.h"
#include "device_density.glsl"

layout(local_size_x = FOVEART_DEVICE_RESOLVE_GROUP) in;
layout(set = 0, binding = 0, std430) readonly buffer RayColors { vec4 ray_colors[]; };  // rgb, depth in metres
layout(set = 0, binding = 2, std430) readonly buffer Control { uint control[]; };
layout(set = 0, binding = 3, std430) buffer Status { uint status[]; };  // device_trace.h
layout(set = 0, binding = 4, std430) buffer Colors { vec4 colors[]; };
layout(set = 0, binding = 5, std430) buffer PointDepth { float point_depth[]; };
// Per rank of a visible point: its rays (device_rays.comp), traced points first.
layout(set = 0, binding = 6, std430) readonly buffer PointRays { DevicePointRays point_rays[]; };
layout(set = 0, binding = 7, std430) readonly buffer Points { DevicePoint points[]; };
layout(set = 0, binding = 8, std430) readonly buffer Levels { DeviceLevel levels[]; };
layout(set = 0, binding = 9, std430) buffer Tiles { uint tile_words[]; };  // the eye's (device_trace.h)

bool not_finite(uint bits) { return (bits & 0x7F800000u) == 0x7F800000u; }
bool invalid(uint bits) { return not_finite(bits) || (bits > 0x80000000u); }  // NaN, infinite, below -0

// The traced point p's luminance into its tile's range (ContentDensity::observe).
void observe(uint p, vec3 rgb) {
  const vec2 screen = points[p].position_radius_grid.xy - canvas_from_screen_px;
  const uint t = density_tile_of(screen, screen_px, tile_px);
  const uint bits = floatBitsToUint(max(density_luminance(rgb, exposure), 0.0));
  atomicMin(tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_MIN, t)], bits);
  atomicMax(tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_MAX, t)], bits);
}

void resolve_point(DevicePointRays rays) {
  vec3 sum = vec3(0.0);
  uint bad = 0u;
  float nearest_m = FOVEART_DEPTH_UNKNOWN;
  for (uint s = 0u; s < rays.ray_count; ++s) {
    const vec4 c = ray_colors[rays.first_ray + s];
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
  const vec3 rgb = sum / float(rays.ray_count);
  colors[rays.point] = vec4(rgb, 1.0);
  point_depth[rays.point] = nearest_m;
  if ((flags & FOVEART_DEVICE_RESOLVE_OBSERVE) != 0u) observe(rays.point, rgb);
}

// A thinned point from its traced parents (none traced: it stays untraced).
void fill_point(uint p) {
  const DeviceLevel level = levels[p];
  const uvec3 parent = level.parents_level.xyz;
  vec3 sum = vec3(0.0);
  float weight = 0.0, depth = FOVEART_DEPTH_UNKNOWN;
  for (uint j = 0u; j < 3u; ++j) {
    if (parent[j] == FOVEART_DEVICE_NO_PARENT || colors[parent[j]].a != 1.0) continue;
    const float w = level.weights[j];
    sum += w * colors[parent[j]].rgb;
    if (weight == 0.0) depth = point_depth[parent[j]];  // the nearest traced parent's
    weight += w;
  }
  if (weight <= 0.0) return;
  colors[p] = vec4(sum / weight, 1.0);
  point_depth[p] = depth;
}

// Tile t's contrast and level from its 3x3 neighbourhood's luminance range (ContentDensity::levels_from_ranges).
void tile_contrast(uint t, uvec2 tiles) {
  const ivec2 at = ivec2(t % tiles.x, t / tiles.x);
  uint lo = 0xFFFFFFFFu, hi = 0u;
  for (int y = max(at.y - 1, 0); y <= min(at.y + 1, int(tiles.y) - 1); ++y)
    for (int x = max(at.x - 1, 0); x <= min(at.x + 1, int(tiles.x) - 1); ++x) {
      const uint n = uint(y) * tiles.x + uint(x);
      lo = min(lo, tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_MIN, n)]);
      hi = max(hi, tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_MAX, n)]);
    }
  const float contrast =
      lo == 0xFFFFFFFFu ? 0.0 : density_tile_contrast(uintBitsToFloat(lo), uintBitsToFloat(hi), dark_luminance);
  tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_CONTRAST, t)] = floatBitsToUint(contrast);
  tile_words[density_tile_word(screen_px, FOVEART_DEVICE_TILE_LEVEL, t)] =
      full_contrast > 0.0 ? density_level(contrast, full_contrast) : FOVEART_DEVICE_FINEST_LEVEL;
}

void main() {
  const uint v = gl_GlobalInvocationID.x;
  if (pass == FOVEART_DEVICE_RESOLVE_CONTRAST) {
    const uvec2 tiles = density_tiles(screen_px, tile_px);
    if (v == 0u) {
      tile_words[FOVEART_DEVICE_TILES_MEASURED] = status[FOVEART_DEVICE_STATUS_INVALID_COMPONENTS] == 0u ? 1u : 0u;
      tile_words[FOVEART_DEVICE_TILES_X] = tiles.x;
      tile_words[FOVEART_DEVICE_TILES_Y] = tiles.y;
      tile_words[FOVEART_DEVICE_TILES_PX] = tile_px;
    }
    if (v < tiles.x * tiles.y) tile_contrast(v, tiles);
    return;
  }
  const uint traced = control[FOVEART_DEVICE_TRACED_POINTS];
  if (pass == FOVEART_DEVICE_RESOLVE_FILL) {
    if (v < control[FOVEART_DEVICE_THINNED_POINTS]) fill_point(point_rays[traced + v].point);
    return;
  }
  if (v >= traced) return;
  // No traced point: no invocation, and the status, cleared, is right (no
  // rays, and no thinned point: a thinned point's parent is visible and traced).
  if (v == 0u) {
    status[FOVEART_DEVICE_STATUS_VISIBLE_POINTS] = control[FOVEART_DEVICE_VISIBLE_POINTS];
    status[FOVEART_DEVICE_STATUS_TRACED_POINTS] = control[FOVEART_DEVICE_TRACED_POINTS];
    status[FOVEART_DEVICE_STATUS_RAYS] = control[0];
    status[FOVEART_DEVICE_STATUS_THINNED_POINTS] = control[FOVEART_DEVICE_THINNED_POINTS];
  }
  resolve_point(point_rays[v]);
}
