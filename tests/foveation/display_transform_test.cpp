// The display transform: exposure, the two tone-mapping curves and the clamp,
// the sRGB bytes, the share of burnt-out pixels, and the encode stage that applies it.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include "foveation/display_transform.hpp"
#include "foveation/rgba8.hpp"
#include "foveation/shader_constants.h"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

TEST(ToneMap, PbrNeutralIsTheIdentityBelowItsRollOffAfterItsSmallToe) {
  // min channel >= 0.08: the toe subtracts exactly 0.04 and the peak stays under 0.76.
  const glm::vec3 c(0.5f, 0.3f, 0.1f);
  const glm::vec3 t = tone_map_pbr_neutral(c);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(t[i], c[i] - 0.04f) << i;
  // Dark colours: x - 6.25 x^2 off each channel, black stays black.
  EXPECT_EQ(tone_map_pbr_neutral(glm::vec3(0.0f)), glm::vec3(0.0f));
  EXPECT_FLOAT_EQ(tone_map_pbr_neutral(glm::vec3(0.04f)).g, 0.04f - (0.04f - 6.25f * 0.04f * 0.04f));
}

TEST(ToneMap, EveryCurveRisesAndStaysFiniteInsideZeroOne) {
  for (ToneMap curve : {ToneMap::none, ToneMap::pbr_neutral, ToneMap::aces}) {
    const DisplayTransform d{1.0f, curve};
    float last = -1.0f;
    for (float x = 0.0f; x < 1000.0f; x = x * 1.25f + 0.01f) {
      const float y = d.apply(glm::vec3(x)).g;
      ASSERT_TRUE(y >= 0.0f && y <= 1.0f) << tone_map_name(curve) << " at " << x;
      ASSERT_GE(y, last) << tone_map_name(curve) << " at " << x;
      last = y;
    }
    // Bad radiance becomes black or white, never NaN.
    const glm::vec3 bad = d.apply(glm::vec3(std::numeric_limits<float>::quiet_NaN(), -1.0f, 0.2f));
    EXPECT_EQ(bad.r, 0.0f) << tone_map_name(curve);
    EXPECT_EQ(bad.g, 0.0f) << tone_map_name(curve);
    const glm::vec3 inf = d.apply(glm::vec3(std::numeric_limits<float>::infinity()));
    EXPECT_TRUE(std::isfinite(inf.b) && inf.b > 0.99f) << tone_map_name(curve);
  }
  // The curves roll highlights off where the clamp cuts them.
  EXPECT_EQ(DisplayTransform({1.0f, ToneMap::none}).apply(glm::vec3(3.0f)).r, 1.0f);
  EXPECT_LT(DisplayTransform({1.0f, ToneMap::pbr_neutral}).apply(glm::vec3(3.0f)).r, 0.99f);
  EXPECT_LT(DisplayTransform({1.0f, ToneMap::aces}).apply(glm::vec3(3.0f)).r, 0.99f);
}

TEST(ToneMap, ExposureScalesRadianceBeforeTheCurve) {
  const DisplayTransform half{0.5f, ToneMap::pbr_neutral};
  const DisplayTransform one{1.0f, ToneMap::pbr_neutral};
  const glm::vec3 c(0.9f, 0.6f, 0.3f);
  EXPECT_EQ(half.apply(c), one.apply(c * 0.5f));
}

TEST(ToneMap, NamesAndShaderIdsRoundTrip) {
  for (ToneMap curve : {ToneMap::none, ToneMap::pbr_neutral, ToneMap::aces})
    EXPECT_EQ(parse_tone_map(tone_map_name(curve)), curve);
  EXPECT_FALSE(parse_tone_map("reinhard"));
  EXPECT_EQ(tone_map_shader_id(ToneMap::none), FOVEART_TONE_MAP_NONE);
  EXPECT_EQ(tone_map_shader_id(ToneMap::pbr_neutral), FOVEART_TONE_MAP_PBR_NEUTRAL);
  EXPECT_EQ(tone_map_shader_id(ToneMap::aces), FOVEART_TONE_MAP_ACES);
}

TEST(ToneMap, ExposureParsesPositiveFiniteNumbersUpToTheLimitOnly) {
  EXPECT_EQ(parse_exposure("0.25"), 0.25f);
  EXPECT_EQ(parse_exposure("1e6"), kMaxExposure);
  for (const char* bad : {"", "0", "-1", "2e6", "nan", "inf", "1x", "auto"})
    EXPECT_FALSE(parse_exposure(bad)) << bad;
}

ImageRgb image_with_bright_share(int bright_of_100, float bright, float rest) {
  ImageRgb im(10, 10);
  for (int i = 0; i < 100; ++i)
    for (int c = 0; c < 3; ++c) im.rgb[std::size_t(i) * 3 + std::size_t(c)] = i < bright_of_100 ? bright : rest;
  return im;
}

TEST(ToneMap, Srgb8IsTheCurveThenTheSrgbEncoding) {
  // Clamp only: 0 -> 0, linear 0.5 -> sRGB 188 (0.7354 x 255), past 1 -> 255; NaN -> 0.
  EXPECT_EQ(kClampOnly.srgb8(glm::vec3(0.0f, 0.5f, 2.0f)), glm::u8vec3(0, 188, 255));
  EXPECT_EQ(kClampOnly.srgb8(glm::vec3(std::numeric_limits<float>::quiet_NaN(), -1.0f, 1.0f)), glm::u8vec3(0, 0, 255));
  // A curve and an exposure come first: 0.5 at exposure 4 is 2, which PBR Neutral rolls off below white.
  const glm::u8vec3 rolled = DisplayTransform{4.0f, ToneMap::pbr_neutral}.srgb8(glm::vec3(0.5f));
  EXPECT_GT(rolled.r, 188);
  EXPECT_LT(rolled.r, 255);
  EXPECT_EQ(rolled, glm::u8vec3(rolled.r));
}

TEST(ToneMap, WhiteClippedFractionCountsPixelsBurntToWhite) {
  const ImageRgb im = image_with_bright_share(10, 100.0f, 0.5f);
  EXPECT_DOUBLE_EQ(white_clipped_fraction(im, kClampOnly), 0.10);
  EXPECT_DOUBLE_EQ(white_clipped_fraction(im, {1.0f, ToneMap::pbr_neutral}), 0.10);  // 100 is far past the knee
  EXPECT_DOUBLE_EQ(white_clipped_fraction(im, {0.01f, ToneMap::pbr_neutral}), 0.0);
  EXPECT_DOUBLE_EQ(white_clipped_fraction(image_with_bright_share(30, 1.5f, 0.5f), kClampOnly), 0.30);
  EXPECT_DOUBLE_EQ(white_clipped_fraction(image_with_bright_share(30, 1.5f, 0.5f), {1.0f, ToneMap::aces}), 0.0);
}

TEST(Rgba8, EncodeAppliesTheDisplayTransform) {
  const ImageRgb im = image_with_bright_share(50, 2.0f, 0.25f);
  Executor& executor = test::executor();
  std::vector<std::uint8_t> clamped(400), toned(400);
  encode_rgba8(im, true, kClampOnly, clamped.data(), executor);
  encode_rgba8(im, true, DisplayTransform{}, toned.data(), executor);
  EXPECT_EQ(clamped[0], 255);
  EXPECT_LT(toned[0], 255);
  EXPECT_GT(toned[0], 200);
  EXPECT_EQ(clamped[3], 255);  // alpha
  // Below the knee PBR Neutral only removes its small toe.
  EXPECT_LT(toned[50 * 4], clamped[50 * 4]);
  EXPECT_GT(toned[50 * 4], clamped[50 * 4] - 30);
}

// The image encode runs whole rows with the curve chosen once: it must give
// the bytes of the per-pixel srgb8() / apply() for every curve, exposure and
// input, NaN, infinities, negatives and the roll-off's knee included.
TEST(Rgba8, EncodeGivesThePerPixelTransformsBytesForEveryCurve) {
  constexpr int kWidth = 61, kHeight = 7;  // rows of odd length, spread over the executor's chunks
  ImageRgb im(kWidth, kHeight);
  const float specials[] = {0.0f, -0.0f, -1.0f, 0.0031308f, 0.04f, 0.08f, 0.7599f, 0.76f, 1.0f, 65504.0f,
                            std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::denorm_min()};
  std::uint32_t x = 12345;
  for (std::size_t i = 0; i < im.rgb.size(); ++i) {
    x = x * 1664525u + 1013904223u;  // LCG: a spread of radiance from 0 to 4
    im.rgb[i] = i % 5 == 0 ? specials[(i / 5) % std::size(specials)] : float(x >> 8) / float(1 << 22);
  }
  for (const ToneMap curve : {ToneMap::none, ToneMap::pbr_neutral, ToneMap::aces}) {
    for (const float exposure : {1.0f, 0.37f, 3.0f}) {
      const DisplayTransform display{exposure, curve};
      for (const bool srgb : {true, false}) {
        std::vector<std::uint8_t> encoded(std::size_t(kWidth) * kHeight * 4);
        encode_rgba8(im, srgb, display, encoded.data(), test::executor());
        for (std::size_t p = 0; p < im.pixel_count(); ++p) {
          const glm::vec3 radiance(im.rgb[p * 3], im.rgb[p * 3 + 1], im.rgb[p * 3 + 2]);
          const glm::u8vec3 want = srgb ? display.srgb8(radiance)
                                        : glm::u8vec3(glm::round(display.apply(radiance) * 255.0f));
          ASSERT_EQ(glm::u8vec3(encoded[p * 4], encoded[p * 4 + 1], encoded[p * 4 + 2]), want)
              << tone_map_name(curve) << " exposure " << exposure << (srgb ? " sRGB" : " UNORM") << " pixel " << p;
          ASSERT_EQ(encoded[p * 4 + 3], 255);
        }
      }
    }
  }
}

}  // namespace
}  // namespace foveart::foveation
