// What turns linear radiance into display values, after reconstruction and
// temporal history, identically for the full and the foveated image and on the
// CPU and the GPU path: an exposure scale, then a tone-mapping curve, then the
// sRGB encoding (srgb.hpp). Accuracy is measured before it, on radiance.
#pragma once

#include <glm/ext/vector_uint3_sized.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "foveation/image.hpp"

namespace foveart::foveation {

enum class ToneMap : std::uint8_t {
  none,         // clamp to [0, 1]
  pbr_neutral,  // Khronos PBR Neutral: identity below 0.76, hue-preserving highlight roll-off
  aces,         // ACES filmic, Narkowicz's fit of the RRT + ODT (2015)
};

struct DisplayTransform {
  float exposure = 1.0f;  // linear scale of radiance before the curve, > 0
  ToneMap tone_map = ToneMap::pbr_neutral;

  bool operator==(const DisplayTransform&) const = default;
  // Radiance -> display-referred linear colour in [0, 1].
  glm::vec3 apply(glm::vec3 radiance) const;
  // Radiance -> the bytes an sRGB display shows: apply(), then the sRGB
  // encoding (srgb.hpp) of each channel.
  glm::u8vec3 srgb8(glm::vec3 radiance) const;
  // pixel_count radiance pixels (RGB floats) -> RGBA8 with alpha 255: each
  // one's srgb8() when `srgb`, else apply() rounded to bytes. The same bytes as
  // those per-pixel calls, with the curve chosen once per run of pixels.
  void encode_rgba8(const float* rgb, std::size_t pixel_count, bool srgb, std::uint8_t* out) const;
};

// The identity up to the clamp: display values are the radiance itself.
inline constexpr DisplayTransform kClampOnly{1.0f, ToneMap::none};

// The share of pixels of a radiance image that show as pure white (all three
// channels at 255 after the transform and the sRGB encoding): burnt out.
double white_clipped_fraction(const ImageRgb& radiance, const DisplayTransform& display);

// Khronos PBR Neutral tone mapping (Khronos 3D Formats WG, 2024).
glm::vec3 tone_map_pbr_neutral(glm::vec3 c);
// ACES filmic approximation (K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2015).
glm::vec3 tone_map_aces(glm::vec3 c);

// "none" | "pbr-neutral" | "aces" (the config key's and the CLI's names).
std::optional<ToneMap> parse_tone_map(std::string_view name);
const char* tone_map_name(ToneMap t);

// A linear exposure written as a number: in (0, kMaxExposure], the layer
// config's range too; nullopt for anything else (text, NaN, 0, negative).
inline constexpr float kMaxExposure = 1.0e6f;
std::optional<float> parse_exposure(std::string_view text);

// The value of shader_constants.h's FOVEART_TONE_MAP_* for each curve.
std::uint32_t tone_map_shader_id(ToneMap t);

}  // namespace foveart::foveation
