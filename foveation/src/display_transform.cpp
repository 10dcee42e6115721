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

// Radiance the curves see: NaN and negatives as 0, and no infinities (the
// largest half float), so that every curve stays finite.
glm::vec3 sanitized(glm::vec3 c) {
  for (int i = 0; i < 3; ++i) c[i] = c[i] >= 0.0f ? std::min(c[i], 65504.0f) : 0.0f;
  return c;
}

}  // namespace

// Khronos PBR Neutral (3D Formats WG, 2024): identity up to 0.76 (after a small
// toe offset of at most 0.04), then the peak rolls off towards 1, desaturating
// by a share that grows with how much it was compressed.
glm::vec3 tone_map_pbr_neutral(glm::vec3 c) {
  constexpr float kStartCompression = 0.8f - 0.04f;
  constexpr float kDesaturation = 0.15f;
  const float x = std::min({c.r, c.g, c.b});
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  c -= offset;
  const float peak = std::max({c.r, c.g, c.b});
  if (peak < kStartCompression) return c;
  constexpr float d = 1.0f - kStartCompression;
  const float new_peak = 1.0f - d * d / (peak + d - kStartCompression);
  c *= new_peak / peak;
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  return glm::mix(c, glm::vec3(new_peak), g);
}

// Narkowicz (2015): x (a x + b) / (x (c x + d) + e) on 0.6 x, his scale that
// matches the reference ACES curve's brightness.
glm::vec3 tone_map_aces(glm::vec3 c) {
  c *= 0.6f;
  return (c * (2.51f * c + 0.03f)) / (c * (2.43f * c + 0.59f) + 0.14f);
}

glm::vec3 DisplayTransform::apply(glm::vec3 radiance) const {
  const glm::vec3 c = sanitized(radiance * exposure);
  glm::vec3 out = c;
  if (tone_map == ToneMap::pbr_neutral) out = tone_map_pbr_neutral(c);
  else if (tone_map == ToneMap::aces) out = tone_map_aces(c);
  return glm::clamp(out, 0.0f, 1.0f);
}

glm::u8vec3 DisplayTransform::srgb8(glm::vec3 radiance) const {
  const glm::vec3 c = apply(radiance);
  return glm::u8vec3(encode_srgb8(c.r), encode_srgb8(c.g), encode_srgb8(c.b));
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
