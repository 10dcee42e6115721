#version 450
// The render cache, pass 4 (ray_cache.glsl): each pixel sum(w L) / sum(w)
// over the rays within its pixel filter, widened to its footprint (pbrt-v4
// 8.8; foveation::RayCache::filter_at, and resolve at footprint 1); the
// gather where no ray reaches it.
#extension GL_GOOGLE_include_directive : require
#include "ray_cache.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size_px.x || p.y >= size_px.y) return;
  const uint index = uint(p.y * size_px.x + p.x);
  const float footprint_px = pixels[index].x;
  const float inv_footprint = 1.0 / footprint_px;
  const vec2 centre = vec2(p) + 0.5;
  const float half_width = filter_kind == FOVEART_RAY_CACHE_FILTER_BOX ? 0.5 : 1.5;
  const vec2 r = vec2(half_width * footprint_px);
  const ivec2 lo = max(ivec2(floor((centre - r) / CELL_PX)) + 1, ivec2(0));
  const ivec2 hi = min(ivec2(ceil((centre + r) / CELL_PX)), cells_xy - 1);  // foveation::filter_window_cells
  vec4 sum = vec4(0.0);
  for (int cy = lo.y; cy <= hi.y; ++cy) {
    for (int cx = lo.x; cx <= hi.x; ++cx) {
      const uint k = uint(cy * cells_xy.x + cx);
      for (uint s = cells[k]; s < cells[k + 1u]; ++s) {
        const CellRay ray = by_cell[s];
        const vec2 t = (ray.sample_px - centre) * inv_footprint;
        if (t.x < -half_width || t.x >= half_width || t.y < -half_width || t.y >= half_width) continue;
        const float w = pixel_filter_weight(t.x) * pixel_filter_weight(t.y);
        sum += vec4(w * vec3(ray.rg, ray.b), w);
      }
    }
  }
  if (sum.w > 0.0) current[index].rgb = sum.rgb / sum.w;
}
