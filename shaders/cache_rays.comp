#version 450
// The render cache, pass 1 (ray_cache.glsl): kept rays projected into this
// view and depth-tested, new rays anchored; each within reach counted into its cell.
#extension GL_GOOGLE_include_directive : require
#include "ray_cache.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
  const uint kept = counts[FOVEART_CACHE_KEPT];
  const uint n = kept + counts[FOVEART_CACHE_ADDED];
  for (uint i = gl_GlobalInvocationID.x; i < n; i += stride()) {
    vec2 q;
    bool within;
    if (i < kept) {
      const Anchor a = anchors_in[i];
      const bool at_infinity = a.point_m_or_direction.w != 0.0;
      const vec3 to_hit = a.point_m_or_direction.xyz - position_m.xyz;
      within = project_direction(at_infinity ? a.point_m_or_direction.xyz : normalize(to_hit), q) && within_reach(q);
      // foveation::kept_ray_covered against the pixel it lands in.
      if (within && q.x >= 0.0 && q.y >= 0.0 && q.x < float(size_px.x) && q.y < float(size_px.y)) {
        const float farthest_new_m = pixels[uint(q.y) * uint(size_px.x) + uint(q.x)].y;
        if (farthest_new_m >= 0.0 &&
            (at_infinity || length(to_hit) > farthest_new_m * (1.0 + KEPT_RAY_OCCLUSION_TOLERANCE))) {
          within = false;
        }
      }
    } else {
      const NewRay r = new_rays[i - kept];
      q = r.sample_px_depth.xy;
      const float depth_m = r.sample_px_depth.z;
      const vec3 direction = eye_ray_direction(q);
      anchors_in[i] = depth_m >= 0.0 && depth_m < DEPTH_FAR
                          ? Anchor(vec4(position_m.xyz + direction * depth_m, 0.0), vec4(r.rgb.rgb, 0.0))
                          : Anchor(vec4(direction, 1.0), vec4(r.rgb.rgb, 0.0));
      within = within_reach(q);
    }
    int cell = -1;
    uint slot = 0u;
    if (within) {  // the grid starts one cell before the image: it holds every ray within reach
      const ivec2 c = ivec2(floor(q / CELL_PX)) + 1;
      if (all(greaterThanEqual(c, ivec2(0))) && all(lessThan(c, cells_xy))) {
        cell = c.y * cells_xy.x + c.x;
        slot = atomicAdd(cells[cell], 1u);
      }
    }
    ray_frame[i] = RayFrame(q, cell, slot);
  }
}
