// foveation/srgb.hpp: the table encoder equals the reference encoding for
// every float it can meet, so the layer's frames and `fovea`'s PNGs agree.
#include "foveation/srgb.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

namespace foveart::foveation {
namespace {

TEST(Srgb, TransferFunctionKnownValues) {
  EXPECT_FLOAT_EQ(linear_to_srgb(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(linear_to_srgb(1.0f), 1.0f);
  EXPECT_NEAR(linear_to_srgb(0.5f), 1.055 * std::pow(0.5, 1.0 / 2.4) - 0.055, 1e-6);  // 0.7354
  EXPECT_NEAR(linear_to_srgb(0.002f), 0.002 * 12.92, 1e-7);                          // linear segment
  for (float s : {0.0f, 0.02f, 0.04045f, 0.3f, 0.7f, 1.0f}) EXPECT_NEAR(linear_to_srgb(srgb_to_linear(s)), s, 2e-6f);
}

TEST(Srgb, ReferenceBytes) {
  EXPECT_EQ(encode_srgb8_reference(0.0f), 0);
  EXPECT_EQ(encode_srgb8_reference(1.0f), 255);
  EXPECT_EQ(encode_srgb8_reference(0.5f), 188);
  EXPECT_EQ(encode_srgb8_reference(0.2f), 124);
}

TEST(Srgb, OutOfRangeAndNonFiniteAreClamped) {
  EXPECT_EQ(encode_srgb8(-1.0f), 0);
  EXPECT_EQ(encode_srgb8(-0.0f), 0);
  EXPECT_EQ(encode_srgb8(2.0f), 255);
  EXPECT_EQ(encode_srgb8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(encode_srgb8(-std::numeric_limits<float>::infinity()), 0);
  EXPECT_EQ(encode_srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(encode_srgb8(std::numeric_limits<float>::denorm_min()), encode_srgb8_reference(1e-45f));
}

// Every byte boundary, from both sides: a sweep over [0, 1] in steps finer
// than any byte's width finds each boundary, bisection pins its exact float,
// and the floats around it encode as the reference does.
TEST(Srgb, TableEqualsReferenceAtEveryByteBoundary) {
  int boundaries = 0;
  std::uint8_t previous = 0;
  std::uint32_t previous_bits = 0;
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  for (std::uint32_t bits = 0; bits <= one; bits += 1 + (bits >> 16)) {  // <= 0.001 in value, bytes are >= 0.0003 wide
    const float c = std::bit_cast<float>(bits);
    const std::uint8_t ref = encode_srgb8_reference(c);
    ASSERT_EQ(encode_srgb8(c), ref) << "c = " << c;
    ASSERT_GE(ref, previous) << "reference not monotonic at c = " << c;
    ASSERT_LE(ref, previous + 1) << "the sweep skipped a byte at c = " << c;
    if (ref != previous) {
      ++boundaries;
      std::uint32_t lo = previous_bits, hi = bits;  // reference(lo) < ref == reference(hi)
      while (hi - lo > 1) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        (encode_srgb8_reference(std::bit_cast<float>(mid)) >= ref ? hi : lo) = mid;
      }
      for (std::uint32_t n = hi - 3; n <= hi + 3; ++n) {
        const float x = std::bit_cast<float>(n);
        ASSERT_EQ(encode_srgb8(x), encode_srgb8_reference(x)) << "near the boundary of byte " << int(ref);
      }
    }
    previous = ref;
    previous_bits = bits;
  }
  EXPECT_EQ(boundaries, 255);
}

}  // namespace
}  // namespace foveart::foveation
