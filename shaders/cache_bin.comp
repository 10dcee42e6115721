#version 450
// The render cache, pass 3 (ray_cache.glsl): each ray within reach into its
// cell's place; the ones young enough appended, one frame older, to the
// other anchor buffer (foveation::RayCache::resolve's keep rule).
#extension GL_GOOGLE_include_directive : require
#include "ray_cache.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
  const uint kept = counts[FOVEART_CACHE_KEPT];
  const uint n = kept + counts[FOVEART_CACHE_ADDED];
  for (uint i = gl_GlobalInvocationID.x; i < n; i += stride()) {
    const RayFrame r = ray_frame[i];
    if (r.cell < 0) continue;  // beyond reach or covered: neither filtered nor kept
    const Anchor a = anchors_in[i];
    by_cell[cells[r.cell] + r.slot] = CellRay(r.sample_px, a.rgb_age.rg, a.rgb_age.b, 0.0);
    const uint age = uint(a.rgb_age.w);
    if (max_age != 0u && age + 1u >= max_age) continue;
    const uint k = atomicAdd(counts[FOVEART_CACHE_KEPT_OUT], 1u);
    if (k < capacity) anchors_out[k] = Anchor(a.point_m_or_direction, vec4(a.rgb_age.rgb, float(age + 1u)));
  }
}
