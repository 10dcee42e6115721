#include "foveation/display_transform.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "foveation/shader_constants.h"
#include "foveation/srgb.hpp"

namespace foveart::foveation {
namespace {

// Khronos PBR Neutral (3D Formats WG, 2024): identity up to 0.76 (after a small
// toe offset of at most 0.04), then the peak rolls off towards 1, desaturating
// by a share that grows with how much it was compressed. Written on plain
// floats with selects rather than branches, so that the image loop below
// runs several pixels per instruction; a value not selected is never used.
inline void pbr_neutral(float& r, float& g, float& b) {
  constexpr float kStartCompression = 0.8f - 0.04f;
  constexpr float kDesaturation = 0.15f;
  constexpr float d = 1.0f - kStartCompression;
  const float x = std::min(r, std::min(g, b));
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  r -= offset, g -= offset, b -= offset;
  const float peak = std::max(r, std::max(g, b));
  const float new_peak = 1.0f - d * d / (peak + d - kStartCompression);
  const float scale = new_peak / peak;
  const float share = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  const bool rolls_off = !(peak < kStartCompression);
  // glm::mix(c * scale, new_peak, share), channel by channel
  r = rolls_off ? r * scale * (1.0f - share) + new_peak * share : r;
  g = rolls_off ? g * scale * (1.0f - share) + new_peak * share : g;
  b = rolls_off ? b * scale * (1.0f - share) + new_peak * share : b;
}

// Narkowicz (2015): x (a x + b) / (x (c x + d) + e) on 0.6 x, his scale that
// matches the reference ACES curve's brightness.
inline float aces(float c) {
  c *= 0.6f;
  return (c * (2.51f * c + 0.03f)) / (c * (2.43f * c + 0.59f) + 0.14f);
}

inline float sanitized(float c) { return c >= 0.0f ? std::min(c, 65504.0f) : 0.0f; }

// apply() for one curve on one pixel, in place: exposure, the radiance the
// curves see (NaN and negatives as 0, no infinities: the largest half float,
// so every curve stays finite), the curve, the clamp to [0, 1].
template <ToneMap kCurve>
inline void display_linear(float& r, float& g, float& b, float exposure) {
  r = sanitized(r * exposure), g = sanitized(g * exposure), b = sanitized(b * exposure);
  if constexpr (kCurve == ToneMap::pbr_neutral) pbr_neutral(r, g, b);
  if constexpr (kCurve == ToneMap::aces) r = aces(r), g = aces(g), b = aces(b);
  r = std::min(std::max(r, 0.0f), 1.0f), g = std::min(std::max(g, 0.0f), 1.0f), b = std::min(std::max(b, 0.0f), 1.0f);
}

template <ToneMap kCurve>
inline glm::vec3 display_linear(glm::vec3 radiance, float exposure) {
  display_linear<kCurve>(radiance.r, radiance.g, radiance.b, exposure);
  return radiance;
}

// The pixel loop of DisplayTransform::encode_rgba8 for one curve and target:
// the curve and the sRGB table are chosen once per run, not per pixel, and
// the curve runs over blocks of pixels laid out channel by channel.
template <ToneMap kCurve, bool kSrgb>
void encode_run(const float* rgb, std::size_t count, float exposure, std::uint8_t* out) {
  constexpr std::size_t kBlock = 16;
  const Srgb8Encoder& encoder = srgb8_encoder();
  float r[kBlock], g[kBlock], b[kBlock];
  for (std::size_t first = 0; first < count; first += kBlock) {
    const std::size_t n = std::min(kBlock, count - first);
    for (std::size_t i = 0; i < kBlock; ++i) {
      const std::size_t p = first + std::min(i, n - 1);  // the tail repeats the last pixel
      r[i] = rgb[p * 3], g[i] = rgb[p * 3 + 1], b[i] = rgb[p * 3 + 2];
    }
    for (std::size_t i = 0; i < kBlock; ++i) display_linear<kCurve>(r[i], g[i], b[i], exposure);
    std::uint8_t* o = out + first * 4;
    for (std::size_t i = 0; i < n; ++i, o += 4) {
      if constexpr (kSrgb) {
        o[0] = encoder(r[i]), o[1] = encoder(g[i]), o[2] = encoder(b[i]);
      } else {
        o[0] = std::uint8_t(std::lround(r[i] * 255.0f)), o[1] = std::uint8_t(std::lround(g[i] * 255.0f));
        o[2] = std::uint8_t(std::lround(b[i] * 255.0f));
      }
      o[3] = 255;
    }
  }
}

template <bool kSrgb>
void encode_run(ToneMap curve, const float* rgb, std::size_t count, float exposure, std::uint8_t* out) {
  switch (curve) {
    case ToneMap::none: return encode_run<ToneMap::none, kSrgb>(rgb, count, exposure, out);
    case ToneMap::pbr_neutral: return encode_run<ToneMap::pbr_neutral, kSrgb>(rgb, count, exposure, out);
    case ToneMap::aces: return encode_run<ToneMap::aces, kSrgb>(rgb, count, exposure, out);
  }
}

}  // namespace

glm::vec3 tone_map_pbr_neutral(glm::vec3 c) {
  pbr_neutral(c.r, c.g, c.b);
  return c;
}

glm::vec3 tone_map_aces(glm::vec3 c) { return glm::vec3(aces(c.r), aces(c.g), aces(c.b)); }

glm::vec3 DisplayTransform::apply(glm::vec3 radiance) const {
  switch (tone_map) {
    case ToneMap::none: return display_linear<ToneMap::none>(radiance, exposure);
    case ToneMap::pbr_neutral: return display_linear<ToneMap::pbr_neutral>(radiance, exposure);
    case ToneMap::aces: return display_linear<ToneMap::aces>(radiance, exposure);
  }
  return display_linear<ToneMap::none>(radiance, exposure);
}

glm::u8vec3 DisplayTransform::srgb8(glm::vec3 radiance) const {
  const glm::vec3 c = apply(radiance);
  return glm::u8vec3(encode_srgb8(c.r), encode_srgb8(c.g), encode_srgb8(c.b));
}

void DisplayTransform::encode_rgba8(const float* rgb, std::size_t pixel_count, bool srgb, std::uint8_t* out) const {
  if (srgb) encode_run<true>(tone_map, rgb, pixel_count, exposure, out);
  else encode_run<false>(tone_map, rgb, pixel_count, exposure, out);
}

double white_clipped_fraction(const ImageRgb& radiance, const DisplayTransform& display) {
  const std::size_t n = radiance.pixel_count();
  if (n == 0) return 0.0;
  std::size_t white = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &radiance.rgb[i * 3];
    white += display.srgb8(glm::vec3(p[0], p[1], p[2])) == glm::u8vec3(255);
  }
  return double(white) / double(n);
}

std::optional<ToneMap> parse_tone_map(std::string_view name) {
  if (name == "none") return ToneMap::none;
  if (name == "pbr-neutral") return ToneMap::pbr_neutral;
  if (name == "aces") return ToneMap::aces;
  return std::nullopt;
}

std::optional<float> parse_exposure(std::string_view text) {
  const std::string owned(text);  // strtof needs the terminating NUL
  char* end = nullptr;
  const float e = std::strtof(owned.c_str(), &end);
  if (owned.empty() || end != owned.c_str() + owned.size() || !std::isfinite(e) || !(e > 0.0f) || e > kMaxExposure)
    return std::nullopt;
  return e;
}

const char* tone_map_name(ToneMap t) {
  switch (t) {
    case ToneMap::none: return "none";
    case ToneMap::pbr_neutral: return "pbr-neutral";
    case ToneMap::aces: return "aces";
  }
  return "none";
}

std::uint32_t tone_map_shader_id(ToneMap t) {
  switch (t) {
    case ToneMap::none: return FOVEART_TONE_MAP_NONE;
    case ToneMap::pbr_neutral: return FOVEART_TONE_MAP_PBR_NEUTRAL;
    case ToneMap::aces: return FOVEART_TONE_MAP_ACES;
  }
  return FOVEART_TONE_MAP_NONE;
}

}  // namespace foveart::foveation
