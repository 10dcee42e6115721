// Content density on the device (thesis 8.2; foveation/content_density.hpp and
// point_rays.hpp are the rule, and the tests check these against them): the
// eye's tiles of the last frame's contrast (the words of device_trace.h), a
// tile's contrast and level, a point's rays. `precise` keeps the arithmetic in
// the C++'s order without fused multiply-adds, so both round alike.
#ifndef FOVEART_DEVICE_DENSITY_GLSL
#define FOVEART_DEVICE_DENSITY_GLSL

#define DENSITY_INFINITY uintBitsToFloat(0x7F800000u)

uvec2 density_tiles(ivec2 screen_px, uint tile_px) {
  return (uvec2(screen_px) + uvec2(tile_px - 1u)) / tile_px;
}

// Tiles of FOVEART_DEVICE_MIN_TILE_PX: every region's size.
uint density_tile_capacity(ivec2 screen_px) {
  const uvec2 t = density_tiles(screen_px, FOVEART_DEVICE_MIN_TILE_PX);
  return t.x * t.y;
}

// The word of `region` (FOVEART_DEVICE_TILE_*) of tile t.
uint density_tile_word(ivec2 screen_px, uint region, uint t) {
  return FOVEART_DEVICE_TILES_HEADER_WORDS + region * density_tile_capacity(screen_px) + t;
}

// ContentDensity::tile_of: points in the visible margin count in the nearest tile.
uint density_tile_of(vec2 screen, ivec2 screen_px, uint tile_px) {
  const uvec2 tiles = density_tiles(screen_px, tile_px);
  const uvec2 at = uvec2(max(ivec2(floor(screen)), ivec2(0))) / tile_px;
  return min(at.y, tiles.y - 1u) * tiles.x + min(at.x, tiles.x - 1u);
}

// Rec. 709 luminance, display-linear (ContentDensity::observe, foveation::rec709_luminance).
float density_luminance(vec3 c, float exposure) {
  precise float l = 0.2126 * c.r + 0.7152 * c.g;
  l = l + 0.0722 * c.b;
  l = l * exposure;
  return l;
}

// foveation::tile_contrast: Michelson contrast with the dark floor.
float density_tile_contrast(float min_luminance, float max_luminance, float dark_luminance) {
  if (!(max_luminance >= min_luminance)) return 0.0;
  precise float floor_sum = max_luminance + min_luminance;
  floor_sum = floor_sum + 2.0 * dark_luminance;
  precise float contrast = (max_luminance - min_luminance) / max(floor_sum, 1e-12);
  return contrast;
}

// foveation::level_for_contrast (thinning on).
uint density_level(float contrast, float full_contrast) {
  if (contrast >= full_contrast) return FOVEART_DEVICE_FINEST_LEVEL;
  uint level = FOVEART_DEVICE_FINEST_LEVEL - 1u;
  for (precise float needed = 0.5 * full_contrast; level > 0u && contrast < needed; needed *= 0.5) --level;
  return level;
}

// foveation::RaysContrastSteps::at: rays_contrast doubled at each step the point lies beyond.
float density_rays_contrast_at(vec2 from_centre_px, float rays_contrast, vec4 step_distance_sq_px2) {
  precise float distance_sq_px2 = from_centre_px.x * from_centre_px.x;
  distance_sq_px2 = distance_sq_px2 + from_centre_px.y * from_centre_px.y;
  float contrast = rays_contrast;
  for (int k = 0; k < 4; ++k)
    if (distance_sq_px2 >= step_distance_sq_px2[k]) contrast *= 2.0;
  return contrast;
}

// foveation::point_ray_count.
uint density_ray_count(uint rays_per_point, float radius_px, float tile_contrast, float rays_contrast) {
  precise float disc_share = min(1.0, radius_px * radius_px);
  precise float contrast_share = min(1.0, tile_contrast / rays_contrast);
  precise float rays = ceil(float(rays_per_point) * disc_share * contrast_share * contrast_share);
  return rays >= 1.0 ? min(rays_per_point, uint(rays)) : 1u;
}

#endif
