// TAA (Karis 2014 clamp, Salvi 2016 variance clip) and the image metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>
#include <random>
#include <vector>

#include "foveation/image_metrics.hpp"
#include "foveation/taa.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

ImageRgb gradient(int w, int h, float offset = 0.0f) {
  ImageRgb im(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* c = im.at(x, y);
      c[0] = offset + 0.5f * float(x) / float(w);
      c[1] = offset + 0.5f * float(y) / float(h);
      c[2] = offset + 0.25f;
    }
  }
  return im;
}

ImageRgb noisy(const ImageRgb& base, std::mt19937& rng, float sigma) {
  std::normal_distribution<float> n(0.0f, sigma);
  ImageRgb im = base;
  for (float& v : im.rgb) v += n(rng);
  return im;
}

class Taa : public ::testing::TestWithParam<TaaConstraint> {};

// The scalar definition TAA had before its row loop was vectorised (per pixel:
// 3x3 taps with clamp-to-edge, constrain the history, blend), in the working
// space (`cur` already tonemapped where the accumulator tonemaps): the fast
// path must reproduce it bit for bit.
ImageRgb taa_reference(const ImageRgb& cur, const ImageRgb& hist, const TaaOptions& o) {
  ImageRgb out(cur.width_px, cur.height_px);
  const int w = cur.width_px, h = cur.height_px;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
      float m1[3] = {0, 0, 0};
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = std::clamp(y + dy, 0, h - 1);
        for (int dx = -1; dx <= 1; ++dx) {
          const float* c = cur.at(std::clamp(x + dx, 0, w - 1), yy);
          for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], c[i]);
            hi[i] = std::max(hi[i], c[i]);
            m1[i] += c[i];
          }
          ++n;
        }
      }
      const float* c = cur.at(x, y);
      const float* hp = hist.at(x, y);
      float hv[3] = {hp[0], hp[1], hp[2]};
      if (o.constraint == TaaConstraint::minmax_clamp) {
        for (int i = 0; i < 3; ++i) hv[i] = std::clamp(hv[i], lo[i], hi[i]);
      } else {
        float mu[3], ext[3];
        for (int i = 0; i < 3; ++i) {
          mu[i] = m1[i] / float(n);
          float s = 0.0f;  // squared deviations, taps in the same order
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              const float d = cur.at(std::clamp(x + dx, 0, w - 1), std::clamp(y + dy, 0, h - 1))[i] - mu[i];
              s += d * d;
            }
          }
          ext[i] = o.variance_gamma * std::sqrt(s / float(n)) + o.clip_floor;
        }
        float t = 1.0f;
        for (int i = 0; i < 3; ++i) {
          const float d = std::abs(hv[i] - mu[i]);
          if (d > ext[i]) t = std::min(t, ext[i] / d);
        }
        for (int i = 0; i < 3; ++i) hv[i] = mu[i] + (hv[i] - mu[i]) * t;
      }
      for (int i = 0; i < 3; ++i) out.at(x, y)[i] = hv[i] + o.current_weight * (c[i] - hv[i]);
    }
  }
  return out;
}

ImageRgb tonemapped(const ImageRgb& linear) {
  ImageRgb out = linear;
  for (std::size_t p = 0; p < out.pixel_count(); ++p) taa_tonemap(out.rgb.data() + 3 * p, out.rgb.data() + 3 * p);
  return out;
}

TEST_P(Taa, MatchesTheScalarDefinitionBitForBit) {
  std::mt19937 rng(7);
  for (const bool tonemap : {false, true}) {
    // Odd sizes, one-pixel-wide and one-row images: every edge case of the clamp.
    for (const auto& [w, h] : {std::pair{37, 23}, std::pair{1, 5}, std::pair{6, 1}, std::pair{2, 2}}) {
      TaaOptions o;
      o.constraint = GetParam();
      o.tonemapped = tonemap;
      TemporalAccumulator taa(o);
      const ImageRgb base = gradient(w, h, 0.8f);  // 0.8 .. 1.3: HDR values in the mix
      const ImageRgb first = noisy(base, rng, 0.2f);
      EXPECT_EQ(taa.accumulate(first, {0, 0}, test::executor()).rgb, first.rgb);  // reset: this frame, exactly
      ImageRgb history = taa.history();
      for (int t = 0; t < 4; ++t) {
        const ImageRgb frame = noisy(base, rng, 0.2f);
        const ImageRgb expected = taa_reference(tonemap ? tonemapped(frame) : frame, history, o);
        const ImageRgb& out = taa.accumulate(frame, {0, 0}, test::executor());
        ASSERT_FALSE(taa.last_was_reset());
        ASSERT_EQ(std::memcmp(taa.history().rgb.data(), expected.rgb.data(), expected.rgb.size() * sizeof(float)), 0)
            << w << "x" << h << " frame " << t << " tonemapped " << tonemap;
        for (std::size_t p = 0; p < out.pixel_count(); ++p) {  // the output: the history mapped back
          float back[3] = {expected.rgb[3 * p], expected.rgb[3 * p + 1], expected.rgb[3 * p + 2]};
          if (tonemap) taa_tonemap_inverse(back, back);
          ASSERT_EQ(std::memcmp(out.rgb.data() + 3 * p, back, sizeof back), 0) << "pixel " << p;
        }
        history = taa.history();
      }
    }
  }
}

TEST_P(Taa, StaticFrameIsAFixedPoint) {
  for (const bool tonemap : {false, true}) {
    TaaOptions o;
    o.constraint = GetParam();
    o.tonemapped = tonemap;
    TemporalAccumulator taa(o);
    const auto frame = gradient(64, 48, 0.9f);  // up to 1.4: HDR too
    EXPECT_EQ(taa.accumulate(frame, {32, 24}, test::executor()).rgb, frame.rgb);
    const ImageRgb history = taa.history();
    for (int t = 0; t < 5; ++t) {
      const auto& out = taa.accumulate(frame, {32, 24}, test::executor());
      EXPECT_EQ(taa.history().rgb, history.rgb);  // the working space holds still, bit for bit
      if (!tonemap) {
        EXPECT_EQ(out.rgb, frame.rgb);
      } else {
        // The tonemap's round trip in float: three roundings and the cancellation
        // in 1 - max(t), which grows with brightness; within 4 ulps up to 1.4.
        for (std::size_t i = 0; i < out.rgb.size(); ++i)
          EXPECT_NEAR(out.rgb[i], frame.rgb[i], 4.0f * std::numeric_limits<float>::epsilon() * frame.rgb[i]) << i;
      }
    }
    EXPECT_EQ(taa.reset_count(), 1u);
  }
}

// accumulate_reprojected: a pixel whose history was rejected (valid 0) is this
// frame exactly, in the output and (tonemapped) in the history; the others blend.
TEST_P(Taa, RejectedHistoryPixelsAreTheCurrentFrameExactly) {
  for (const bool tonemap : {false, true}) {
    TaaOptions o;
    o.constraint = GetParam();
    o.tonemapped = tonemap;
    TemporalAccumulator taa(o);
    const ImageRgb a = gradient(13, 7, 0.9f), b = gradient(13, 7, 0.95f);
    taa.accumulate(a, {6, 3}, test::executor());
    std::vector<std::uint8_t> valid(a.pixel_count(), 1);
    for (std::size_t p = 0; p < valid.size(); p += 3) valid[p] = 0;
    const ImageRgb warped = taa.history();
    const ImageRgb& out = taa.accumulate_reprojected(b, warped, valid, {6, 3}, test::executor());
    ASSERT_FALSE(taa.last_was_reset());
    const ImageRgb working = tonemap ? tonemapped(b) : b;
    for (std::size_t p = 0; p < valid.size(); ++p) {
      const bool same = std::memcmp(out.rgb.data() + 3 * p, b.rgb.data() + 3 * p, 3 * sizeof(float)) == 0;
      EXPECT_EQ(same, valid[p] == 0) << "pixel " << p << " tonemapped " << tonemap;
      if (valid[p] == 0) {
        EXPECT_EQ(std::memcmp(taa.history().rgb.data() + 3 * p, working.rgb.data() + 3 * p, 3 * sizeof(float)), 0);
      }
    }
  }
}

// Karis 2014: a firefly (one sample far brighter than its neighbours) enters a
// linear blend with alpha times its brightness and stays for many frames; the
// tonemapped blend bounds what one sample can add.
TEST_P(Taa, TonemappedBlendKeepsAFireflyFromDominating) {
  ImageRgb flat(9, 9);
  std::fill(flat.rgb.begin(), flat.rgb.end(), 0.2f);
  ImageRgb firefly = flat;
  std::fill_n(firefly.at(4, 4), 3, 100.0f);
  float peak[2] = {};
  for (const bool tonemap : {false, true}) {
    TaaOptions o;
    o.constraint = GetParam();
    o.tonemapped = tonemap;
    TemporalAccumulator taa(o);
    for (int t = 0; t < 8; ++t) taa.accumulate(flat, {4, 4}, test::executor());
    peak[tonemap] = taa.accumulate(firefly, {4, 4}, test::executor()).at(4, 4)[0];
  }
  EXPECT_NEAR(peak[false], 0.2f + 0.1f * (100.0f - 0.2f), 1e-3f);  // linear: alpha of the firefly
  // Tonemapped: 1/6 + 0.1 (100/101 - 1/6) = 0.2492 -> 0.2492 / (1 - 0.2492) = 0.332.
  EXPECT_NEAR(peak[true], 0.3319f, 1e-3f);
}

TEST(TaaTonemap, RoundTripsAndBoundsHugeValues) {
  const float colours[][3] = {{0.0f, 0.0f, 0.0f}, {0.25f, 0.5f, 1.0f}, {12.0f, 3.0f, 0.5f}, {-0.1f, -0.2f, -0.3f}};
  for (const auto& c : colours) {
    float t[3], back[3];
    taa_tonemap(c, t);
    for (float v : t) EXPECT_LT(v, 1.0f);
    taa_tonemap_inverse(t, back);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], c[i], 4e-7f * std::max(1.0f, std::abs(c[i]))) << i;
  }
  const float huge[3] = {1e30f, 0.0f, 0.0f};
  float t[3], back[3];
  taa_tonemap(huge, t);
  taa_tonemap_inverse(t, back);
  EXPECT_TRUE(std::isfinite(back[0]));  // 1 - max(t) rounds to 0: the denominator is held at 2^-16
  EXPECT_EQ(back[0], 65536.0f);
}

TEST_P(Taa, StaticNoisySceneConvergesAndFlickersLess) {
  TaaOptions o;
  o.constraint = GetParam();
  TemporalAccumulator taa(o);
  const auto base = gradient(64, 48);
  std::mt19937 rng(1);
  const float sigma = 0.05f;
  ImageRgb prev_in, prev_out;
  double flicker_in = 0, flicker_out = 0;
  double first_error = 0, last_error = 0;
  for (int t = 0; t < 64; ++t) {
    const auto in = noisy(base, rng, sigma);
    const ImageRgb out = taa.accumulate(in, {32, 24}, test::executor());
    const double err = mean_abs_difference(out, base);
    if (t == 0) first_error = err;
    last_error = err;
    if (t > 0) {
      flicker_in += mean_abs_difference(in, prev_in);
      flicker_out += mean_abs_difference(out, prev_out);
    }
    prev_in = in;
    prev_out = out;
  }
  EXPECT_LT(last_error, 0.7 * first_error);
  EXPECT_LT(flicker_out, 0.5 * flicker_in);
  EXPECT_EQ(taa.reset_count(), 1u);
}

TEST_P(Taa, ConvergesToANewStaticScene) {
  TaaOptions o;
  o.constraint = GetParam();
  TemporalAccumulator taa(o);
  const auto a = gradient(32, 32, 0.0f), b = gradient(32, 32, 0.3f);
  for (int t = 0; t < 10; ++t) taa.accumulate(a, {16, 16}, test::executor());
  double err = 1.0;
  for (int t = 0; t < 64; ++t) {
    const double e = mean_abs_difference(taa.accumulate(b, {16, 16}, test::executor()), b);
    EXPECT_LE(e, err + 1e-7);
    err = e;
  }
  EXPECT_LT(err, 1e-3);
}

TEST_P(Taa, GazeJumpResetsHistory) {
  TaaOptions o;
  o.constraint = GetParam();
  TemporalAccumulator taa(o);
  const auto a = gradient(64, 48, 0.0f), c = gradient(64, 48, 0.4f);
  for (int t = 0; t < 8; ++t) taa.accumulate(a, {10, 10}, test::executor());
  // A small move keeps the history: the output is not the new frame yet.
  const ImageRgb kept = taa.accumulate(c, {15, 10}, test::executor());
  EXPECT_FALSE(taa.last_was_reset());
  EXPECT_NE(kept.rgb, c.rgb);
  // A jump beyond reset_distance_px: the output is exactly the current frame.
  const ImageRgb jumped = taa.accumulate(c, {60, 40}, test::executor());
  EXPECT_TRUE(taa.last_was_reset());
  EXPECT_EQ(jumped.rgb, c.rgb);
  // A saccade flag resets even without motion.
  taa.accumulate(a, {60, 40}, test::executor(), /*saccade=*/true);
  EXPECT_TRUE(taa.last_was_reset());
  // Only its first frame: while the flag stays set, the history accumulates again.
  const ImageRgb during = taa.accumulate(c, {60, 40}, test::executor(), /*saccade=*/true);
  EXPECT_FALSE(taa.last_was_reset());
  EXPECT_NE(during.rgb, c.rgb);
  taa.accumulate(c, {60, 40}, test::executor());
  EXPECT_FALSE(taa.last_was_reset());
  taa.accumulate(c, {60, 40}, test::executor(), /*saccade=*/true);  // the next saccade's onset
  EXPECT_TRUE(taa.last_was_reset());
  EXPECT_EQ(taa.reset_count(), 4u);
}

INSTANTIATE_TEST_SUITE_P(Constraints, Taa,
                         ::testing::Values(TaaConstraint::minmax_clamp, TaaConstraint::variance_clip));

}  // namespace
}  // namespace foveart::foveation
