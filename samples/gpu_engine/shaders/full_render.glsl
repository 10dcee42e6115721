// The full render (engine::render_full) of one pixel: spp rays through
// pixel + pixel_jitter(y * W + x, s, seed) (box filter), averaged; w = the
// first ray's hit distance. Rays as foveation::eye_ray_direction makes them.
// Set 1: the output pixels; push constants: the view. Shared by full.comp
// (compute) and full.rgen (ray-tracing pipeline); include trace_core.glsl first.
#ifndef FOVEART_GPU_FULL_RENDER_GLSL
#define FOVEART_GPU_FULL_RENDER_GLSL

#include "eye_rays.glsl"
#include "jitter.glsl"

layout(std430, set = 1, binding = 0) writeonly buffer Pixels { vec4 pixels[]; };

layout(push_constant) uniform View {
  vec4 tans;         // tan of the left, right, up, down angles (eye_frustum)
  vec4 position_m;   // xyz
  vec4 orientation;  // normalised quaternion xyzw (eye_pose)
  uvec4 size_spp_seed;  // width, height, spp, seed low word
  uvec4 seed_hi;        // x: seed high word
} view;

// Renders pixel px when it lies in the view; counts its rays.
void render_pixel(uvec2 px) {
  const uint w = view.size_spp_seed.x, h = view.size_spp_seed.y, spp = view.size_spp_seed.z;
  if (px.x < w && px.y < h) {
    const uint pixel = px.y * w + px.x;
    const uvec2 seed = uvec2(view.size_spp_seed.w, view.seed_hi.x);
    vec3 sum = vec3(0.0);
    float depth_m = 0.0;
    uvec3 secondary = uvec3(0u);
    for (uint s = 0u; s < spp; ++s) {
      const vec2 sample_px = vec2(px) + pixel_jitter(pixel, s, seed, false);
      const vec4 c = trace_path(view.position_m.xyz,
                                  eye_ray_direction(view.tans, view.orientation, vec2(view.size_spp_seed.xy), sample_px),
                                  secondary);
      sum += c.rgb;
      if (s == 0u) depth_m = c.w;
    }
    const float inv = 1.0 / float(spp);
    pixels[pixel] = vec4(sum * inv, depth_m);
    count_rays(spp, secondary);
  }
}

#endif
