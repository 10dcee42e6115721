// sRGB transfer function (IEC 61966-2-1) and its 8-bit encoding: one
// definition for every image FoveaRT writes (layer swapchains, `fovea` PNGs,
// engine textures), so frames from different paths compare bit for bit.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <algorithm>

namespace foveart::foveation {

// Rec. 709 (ITU-R BT.709) luminance of linear RGB in sRGB's primaries, summed in this order (the
// device's contrast pass, device_density.glsl, sums alike).
inline float rec709_luminance(float r, float g, float b) {
  return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

// IEC 61966-2-1: encoded [0,1] -> linear [0,1].
inline float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// IEC 61966-2-1: linear [0,1] -> encoded [0,1].
inline float linear_to_srgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

// The reference 8-bit encoding: round(linear_to_srgb(clamp(c, 0, 1)) * 255);
// NaN encodes as 0. Costs a pow per call: for images use encode_srgb8.
inline std::uint8_t encode_srgb8_reference(float c) {
  if (!(c > 0.0f)) return 0;
  if (c >= 1.0f) return 255;
  return static_cast<std::uint8_t>(std::lround(linear_to_srgb(c) * 255.0f));
}

// encode_srgb8_reference, bit-exact for every float, from a table: the
// smallest float that encodes to each byte (found by bisection over float bit
// patterns, so the boundaries are the reference's own), and per 1/4096 bucket
// of [0,1) the byte at its start. A lookup steps over the few bytes a bucket
// spans with a fixed number of compares (no branch that depends on the value).
class Srgb8Encoder {
 public:
  Srgb8Encoder() {
    threshold_[0] = 0.0f;
    for (int byte = 1; byte < 256; ++byte) {
      std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);  // reference(hi) = 255 >= byte
      while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (encode_srgb8_reference(std::bit_cast<float>(mid)) >= byte) hi = mid; else lo = mid + 1;
      }
      threshold_[byte] = std::bit_cast<float>(lo);
    }
    threshold_[256] = std::numeric_limits<float>::infinity();  // no byte past 255
    for (std::size_t i = 0; i < kBuckets; ++i) {
      bucket_start_[i] = encode_srgb8_reference(static_cast<float>(i) / static_cast<float>(kBuckets));
    }
    // A value in bucket i encodes to at most the next bucket's first byte (255 past the last).
    for (std::size_t i = 0; i < kBuckets; ++i) {
      const unsigned next = i + 1 < kBuckets ? bucket_start_[i + 1] : 255u;
      steps_ = std::max(steps_, next - bucket_start_[i]);
    }
  }

  std::uint8_t operator()(float c) const {
    if (!(c > 0.0f)) return 0;
    if (c >= 1.0f) return 255;
    // c * 4096 scales by a power of two: exact, so the bucket's start is <= c.
    unsigned byte = bucket_start_[static_cast<std::size_t>(c * static_cast<float>(kBuckets))];
    for (unsigned k = 0; k < steps_; ++k) byte += c >= threshold_[byte + 1] ? 1u : 0u;
    return static_cast<std::uint8_t>(byte);
  }

 private:
  static constexpr std::size_t kBuckets = 4096;
  std::array<float, 257> threshold_{};
  std::array<std::uint8_t, kBuckets> bucket_start_{};
  unsigned steps_ = 0;  // the most bytes one bucket spans
};

// The one table of encode_srgb8, built on first use: a loop over pixels takes
// it once rather than passing the static's guard per channel.
inline const Srgb8Encoder& srgb8_encoder() {
  static const Srgb8Encoder encoder;
  return encoder;
}

// Linear -> sRGB byte, equal to encode_srgb8_reference for every float.
inline std::uint8_t encode_srgb8(float linear) { return srgb8_encoder()(linear); }

}  // namespace foveart::foveation
