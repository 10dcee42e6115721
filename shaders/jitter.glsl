// The frame's ray jitter on the device: foveation/src/ray_samples.cpp
// (pixel_jitter, unit_disc_sample) and its SplitMix64 hash
// (foveation/src/hash.hpp) in 32-bit words, so no shaderInt64 is needed.
// A 64-bit value is uvec2(low word, high word). pixel_jitter is bit-exact;
// unit_disc_sample rounds its uniforms to float where the CPU keeps doubles
// (positions agree within 1e-6 of the disc's radius).
#ifndef FOVEART_JITTER_GLSL
#define FOVEART_JITTER_GLSL

uvec2 add64(uvec2 a, uvec2 b) {
  uint carry;
  const uint lo = uaddCarry(a.x, b.x, carry);
  return uvec2(lo, a.y + b.y + carry);
}

uvec2 mul64(uvec2 a, uvec2 b) {
  uint hi, lo;
  umulExtended(a.x, b.x, hi, lo);
  return uvec2(lo, hi + a.x * b.y + a.y * b.x);
}

// a >> n for 0 < n < 32.
uvec2 shr64(uvec2 a, uint n) { return uvec2((a.x >> n) | (a.y << (32u - n)), a.y >> n); }

// SplitMix64 finaliser (Steele, Lea & Flood 2014).
uvec2 mix64(uvec2 z) {
  z = add64(z, uvec2(0x7F4A7C15u, 0x9E3779B9u));
  z = mul64(z ^ shr64(z, 30u), uvec2(0x1CE4E5B9u, 0xBF58476Du));
  z = mul64(z ^ shr64(z, 27u), uvec2(0x133111EBu, 0x94D049BBu));
  return z ^ shr64(z, 31u);
}

// Two uniforms in [0, 1) of 24 bits each: bits 40..63 and 16..39.
vec2 unit_pair(uvec2 h) {
  return vec2(float(h.y >> 8u), float(((h.x >> 16u) | (h.y << 16u)) & 0xFFFFFFu)) * (1.0 / 16777216.0);
}

// Uniform in [0, 1) from the top bits (the CPU's unit_double, rounded to float).
float unit_float(uvec2 h) { return float(h.y >> 8u) * (1.0 / 16777216.0); }

// foveation::pixel_jitter: sample s of pixel `pixel` (y * W + x, as 64 bits)
// from the pixel's corner; box in [0, 1)^2, bspline2 (the sum of three) in (-1, 2)^2.
vec2 pixel_jitter(uvec2 pixel, uint s, uvec2 seed, bool bspline2) {
  const uvec2 sample_key = mix64(add64(uvec2(s, 0u), uvec2(0u, seed.x)));  // s + (seed << 32)
  const uvec2 h = mix64(mul64(pixel, uvec2(0x000001B3u, 0x00000100u)) ^ sample_key);
  if (!bspline2) return unit_pair(h);
  const uvec2 h2 = mix64(h), h3 = mix64(h2);
  return unit_pair(h) + unit_pair(h2) + unit_pair(h3) - vec2(1.0);
}

vec2 pixel_jitter(uint pixel, uint s, uvec2 seed, bool bspline2) {
  return pixel_jitter(uvec2(pixel, 0u), s, seed, bspline2);
}

// foveation::pixel_sample_px: sample s of the pixel-grid point at centre_px on
// a screen width_px wide; a point in the margin left of or above the screen
// has a negative pixel index, which the CPU wraps as 64 bits.
vec2 pixel_sample_px(vec2 centre_px, uint s, uvec2 seed, int width_px, bool bspline2) {
  const ivec2 corner = ivec2(centre_px);  // truncated toward zero, as the CPU's int()
  const int pixel = corner.y * width_px + corner.x;
  return vec2(corner) + pixel_jitter(uvec2(uint(pixel), pixel < 0 ? 0xFFFFFFFFu : 0u), s, seed, bspline2);
}

// foveation::unit_disc_sample: sample s of point `point` inside the unit disc.
vec2 unit_disc_sample(uvec2 seed, uint point, uint s) {
  const uvec2 key = mix64(seed ^ mix64(uvec2((point << 16u) ^ s, point >> 16u)));
  const float r = sqrt(unit_float(key));
  const float theta = 6.2831853071795864 * unit_float(mix64(key));
  return vec2(r * cos(theta), r * sin(theta));
}

#endif
