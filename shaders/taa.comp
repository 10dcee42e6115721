#version 450
// Temporal accumulation of one eye (thesis 2.5, 6.1), the GPU twin of
// foveation::TemporalAccumulator: the history is constrained to the current
// frame's 3x3 neighbourhood (clamp to edge) by min/max clamping (Karis 2014)
// or variance clipping towards the mean (Salvi 2016), then blended with the
// current frame. A reset (decided on the CPU, one rule for both paths) copies
// the current frame.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push {
  ivec2 size_px;
  float current_weight;  // alpha of the blend
  float variance_gamma;  // box mu +- gamma sigma
  uint constraint;       // 0 min/max clamp, 1 variance clip
  uint reset;            // 1: output = current
  float clip_floor;      // the box's least half-width (TaaOptions::clip_floor)
};

vec3 at(ivec2 p) {
  p = clamp(p, ivec2(0), size_px - 1);
  return current[p.y * size_px.x + p.x].rgb;
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size_px.x || p.y >= size_px.y) return;
  const uint i = uint(p.y * size_px.x + p.x);
  const vec3 cur = current[i].rgb;
  if (reset != 0u) {
    history_out[i] = vec4(cur, 1.0);
    return;
  }
  vec3 v = history_in[i].rgb;
  if (constraint == 0u) {
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
  history_out[i] = vec4(v + current_weight * (cur - v), 1.0);
}
