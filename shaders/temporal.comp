#version 450
// Temporal accumulation of one eye (thesis 2.5, 6.1), the GPU twin of
// foveation::TemporalAccumulator and foveation::reproject_history: when the
// view moved, each pixel finds its surface in the last view (by rotation, or
// through its depth for parallax) and takes the last output there
// (bilinear, or Catmull-Rom clamped to the 2x2 around), unless that is off-screen or the last depth there disagrees
// (disocclusion); the history is then constrained to the current frame's 3x3
// neighbourhood (clamp to edge) by min/max clamping (Karis 2014) or variance
// clipping towards the mean (Salvi 2016) and blended with the current frame.
// A reset (decided on the CPU, one rule for both paths) copies the current frame.
// A faulted frame (common.glsl frame_faulted) keeps the history as it was.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "quat.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
#include "gpu/shader_interface/temporal.h"

#define DISOCCLUSION_TOLERANCE FOVEART_DISOCCLUSION_TOLERANCE

vec3 at(ivec2 p) {
  p = clamp(p, ivec2(0), size_px - 1);
  return current[p.y * size_px.x + p.x].rgb;
}

// The last output (rgb) and its depth (a) at pixel p, clamped to the edge.
vec4 last_texel(ivec2 p) {
  p = clamp(p, ivec2(0), size_px - 1);
  return history_in[p.y * size_px.x + p.x];
}
vec3 last_at(ivec2 p) { return last_texel(p).rgb; }

// foveation::HistorySampling::catmull_rom's weights of the 4 taps around fraction t.
vec4 catmull_rom_weights(float t) {
  const float t2 = t * t, t3 = t2 * t;
  return 0.5 * vec4(-t3 + 2.0 * t2 - t, 3.0 * t3 - 5.0 * t2 + 2.0, -3.0 * t3 + 4.0 * t2 + t, t3 - t2);
}

// The last output where this pixel's surface was; false when rejected.
bool reprojected_history(ivec2 p, float depth, out vec3 history) {
  history = vec3(0.0);
  const vec2 uv = (vec2(p) + 0.5) / vec2(size_px);
  const vec3 v = normalize(vec3(tan_view.x + uv.x * (tan_view.y - tan_view.x),
                                tan_view.z + uv.y * (tan_view.w - tan_view.z), -1.0));
  const bool known = depth >= 0.0, finite = known && depth < DEPTH_FAR;
  vec3 seen = rotate(last_from_view_q, v);
  float expected = DEPTH_FAR;
  if (finite) {
    seen = rotate(last_from_view_q, v * depth) + last_from_view_t.xyz;
    expected = length(seen);
    seen /= expected;
  }
  if (!(seen.z < 0.0)) return false;
  const vec2 t = seen.xy / -seen.z;
  const vec2 s = vec2((t.x - tan_last.x) / (tan_last.y - tan_last.x), (t.y - tan_last.z) / (tan_last.w - tan_last.z)) *
                 vec2(size_px);
  if (!(s.x >= 0.0 && s.x < float(size_px.x) && s.y >= 0.0 && s.y < float(size_px.y))) return false;
  const ivec2 n = min(ivec2(s), size_px - 1);
  if (known) {  // P's distance within the last depths of the 3x3 pixels around (a jittered ray's each)
    float lo = 3.4e38, hi = -1.0;
    bool unknown = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const float before = last_texel(n + ivec2(dx, dy)).a;
        if (before < 0.0) {
          unknown = true;
        } else {
          lo = min(lo, before);
          hi = max(hi, before);
        }
      }
    const bool agree = unknown || (expected >= DEPTH_FAR ? hi >= DEPTH_FAR
                                                          : expected >= lo * (1.0 - DISOCCLUSION_TOLERANCE) &&
                                                                expected <= hi * (1.0 + DISOCCLUSION_TOLERANCE));
    if (!agree) return false;
  }
  const vec2 f = s - 0.5;
  const ivec2 i0 = ivec2(floor(f));
  const vec2 a = f - vec2(i0);
  const vec3 c00 = last_at(i0), c10 = last_at(i0 + ivec2(1, 0));
  const vec3 c01 = last_at(i0 + ivec2(0, 1)), c11 = last_at(i0 + ivec2(1, 1));
  if (reproject == FOVEART_REPROJECT_BILINEAR) {
    const vec3 top = c00 + a.x * (c10 - c00), bottom = c01 + a.x * (c11 - c01);
    history = top + a.y * (bottom - top);
    return true;
  }
  const vec4 wx = catmull_rom_weights(a.x), wy = catmull_rom_weights(a.y);
  vec3 sum = vec3(0.0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) sum += (wx[i] * wy[j]) * last_at(i0 + ivec2(i - 1, j - 1));
  history = min(max(sum, min(min(c00, c10), min(c01, c11))), max(max(c00, c10), max(c01, c11)));
  return true;
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size_px.x || p.y >= size_px.y) return;
  const uint i = uint(p.y * size_px.x + p.x);
  if (frame_faulted()) {
    history_out[i] = history_in[i];
    return;
  }
  const vec4 cur = current[i];
  vec3 v = history_in[i].rgb;
  if (reset != 0u || (reproject != FOVEART_REPROJECT_NONE && !reprojected_history(p, cur.a, v))) {
    history_out[i] = cur;  // no history: this frame alone
    return;
  }
  if (constraint == FOVEART_HISTORY_MIN_MAX_CLAMP) {
    vec3 lo = vec3(1.0 / 0.0), hi = vec3(-1.0 / 0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const vec3 c = at(p + ivec2(dx, dy));
        lo = min(lo, c);
        hi = max(hi, c);
      }
    v = min(max(v, lo), hi);
  } else {
    // Mean, then the variance from squared deviations (two passes, as the CPU:
    // E[c^2] - mu^2 cancels in a flat box and the clip would hinge on rounding).
    vec3 m1 = vec3(0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) m1 += at(p + ivec2(dx, dy));
    const vec3 mu = m1 / 9.0;
    vec3 s = vec3(0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const vec3 d = at(p + ivec2(dx, dy)) - mu;
        s += d * d;
      }
    const vec3 e = variance_gamma * sqrt(s / 9.0) + clip_floor;
    const vec3 d = abs(v - mu);
    float t = 1.0;  // largest scale of (v - mu) that stays inside the box
    for (int c = 0; c < 3; ++c)
      if (d[c] > e[c]) t = min(t, e[c] / d[c]);
    v = mu + (v - mu) * t;
  }
  history_out[i] = vec4(v + current_weight * (cur.rgb - v), cur.a);
}
