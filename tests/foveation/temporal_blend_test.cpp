// TAA (Karis 2014 clamp, Salvi 2016 variance clip) and the image metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <random>
#include <vector>

#include <metrics/image_metrics.hpp>
#include "foveation/temporal_blend.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

using metrics::mean_abs_difference;

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

class Taa : public ::testing::TestWithParam<HistoryClip> {};

// The scalar definition TAA had before its row loop was vectorised (per pixel:
// 3x3 taps with clamp-to-edge, constrain the history, blend): the fast path
// must reproduce it bit for bit.
ImageRgb taa_reference(const ImageRgb& cur, const ImageRgb& hist, const TemporalOptions& o, float weight) {
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
      if (o.constraint == HistoryClip::minmax_clamp) {
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
      for (int i = 0; i < 3; ++i) out.at(x, y)[i] = hv[i] + weight * (c[i] - hv[i]);
    }
  }
  return out;
}

TEST_P(Taa, MatchesTheScalarDefinitionBitForBit) {
  std::mt19937 rng(7);
  // Odd sizes, one-pixel-wide and one-row images: every edge case of the clamp.
  for (const auto& [w, h] : {std::pair{37, 23}, std::pair{1, 5}, std::pair{6, 1}, std::pair{2, 2}}) {
    TemporalOptions o;
    o.constraint = GetParam();
    o.mean_while_young = true;  // both weights: the young mean's 1 / k, then current_weight
    TemporalAccumulator taa(o);
    const ImageRgb base = gradient(w, h);
    ImageRgb history = noisy(base, rng, 0.2f);
    taa.accumulate(history, {0, 0}, test::executor());  // reset: history = this frame
    // Frames 2..13 after the reset: the young history's 1 / k, then current_weight.
    for (int t = 0; t < 12; ++t) {
      const ImageRgb frame = noisy(base, rng, 0.2f);
      const float weight = std::max(o.current_weight, 1.0f / float(t + 2));
      const ImageRgb expected = taa_reference(frame, history, o, weight);
      const ImageRgb& out = taa.accumulate(frame, {0, 0}, test::executor());
      ASSERT_FALSE(taa.last_was_reset());
      ASSERT_EQ(taa.frame_weight(), weight) << "frame " << t;
      ASSERT_EQ(std::memcmp(out.rgb.data(), expected.rgb.data(), out.rgb.size() * sizeof(float)), 0)
          << w << "x" << h << " frame " << t;
      history = out;
    }
  }
}

TEST_P(Taa, StaticFrameIsAFixedPoint) {
  TemporalOptions o;
  o.constraint = GetParam();
  TemporalAccumulator taa(o);
  const auto frame = gradient(64, 48);
  for (int t = 0; t < 5; ++t) {
    const auto& out = taa.accumulate(frame, {32, 24}, test::executor());
    EXPECT_EQ(out.rgb, frame.rgb);
  }
  EXPECT_EQ(taa.reset_count(), 1u);
}

TEST_P(Taa, StaticNoisySceneConvergesAndFlickersLess) {
  TemporalOptions o;
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
  TemporalOptions o;
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

// A checkerboard of 0 and 1: every 3x3 neighbourhood spans both, so a history
// between 0.3 and 0.7 blends unclipped under either constraint.
ImageRgb checkerboard(int w, int h, float low, float high) {
  ImageRgb im(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int i = 0; i < 3; ++i) im.at(x, y)[i] = ((x + y + i) % 2 == 0) ? low : high;
    }
  }
  return im;
}

// The exponential blend's alpha per ray (a young history's mean needs none:
// TaaFrameWeight below), so the young mean is off here.
TEST_P(Taa, AFrameOfNRaysBlendsAsNOneRayFrames) {
  TemporalOptions one_ray;
  one_ray.constraint = GetParam();
  one_ray.mean_while_young = false;
  const ImageRgb start = checkerboard(16, 12, 0.4f, 0.6f), target = checkerboard(16, 12, 0.0f, 1.0f);
  for (int rays : {2, 4, 16}) {
    const TemporalOptions n_rays = temporal_options_for_rays(one_ray, rays);
    TemporalAccumulator once(n_rays), in_turn(one_ray);
    once.accumulate(start, {8, 6}, test::executor());
    in_turn.accumulate(start, {8, 6}, test::executor());
    const ImageRgb& blended_once = once.accumulate(target, {8, 6}, test::executor());
    ASSERT_EQ(once.frame_weight(), n_rays.current_weight);
    for (int i = 0; i < rays; ++i) in_turn.accumulate(target, {8, 6}, test::executor());
    ASSERT_EQ(in_turn.frame_weight(), one_ray.current_weight);
    ASSERT_EQ(blended_once.rgb.size(), in_turn.history().rgb.size());
    double worst = 0.0;
    for (std::size_t v = 0; v < blended_once.rgb.size(); ++v) {
      worst = std::max(worst, std::abs(double(blended_once.rgb[v]) - double(in_turn.history().rgb[v])));
    }
    EXPECT_LT(worst, 1e-6) << rays << " rays";
    // And the history did move: the blend was not clipped to the target.
    EXPECT_GT(mean_abs_difference(blended_once, target), 0.05) << rays << " rays";
  }
  // One ray (and a nonsensical 0): the options as given, bit for bit.
  for (int rays : {1, 0}) {
    const TemporalOptions same = temporal_options_for_rays(one_ray, rays);
    EXPECT_EQ(std::memcmp(&same.current_weight, &one_ray.current_weight, sizeof(float)), 0) << rays << " rays";
  }
}

// After a reset the history is the plain mean of its frames until 1 / k falls
// to current_weight (progressive accumulation), then the exponential blend.
// Frames of a 0/1 checkerboard in a random phase each: every 3x3 box spans 0
// and 1, and every mean lies between, so the min/max clamp never acts; the
// variance clip is widened (gamma 4) to act as little.
TEST_P(Taa, AYoungHistoryIsTheMeanOfItsFrames) {
  TemporalOptions o;
  o.constraint = GetParam();
  o.mean_while_young = true;
  o.variance_gamma = 4.0f;
  const int young = int(std::lround(1.0f / o.current_weight));  // 10 frames at alpha 0.1
  std::mt19937 rng(3);
  std::vector<ImageRgb> frames;
  for (int t = 0; t < young + 2; ++t) {
    frames.push_back(rng() % 2 == 0 ? checkerboard(17, 9, 0.0f, 1.0f) : checkerboard(17, 9, 1.0f, 0.0f));
  }
  TemporalAccumulator taa(o);
  std::vector<double> sum(frames[0].rgb.size(), 0.0);
  for (int t = 0; t < young; ++t) {
    const ImageRgb& out = taa.accumulate(frames[std::size_t(t)], {8, 4}, test::executor());
    EXPECT_EQ(taa.last_was_reset(), t == 0);
    EXPECT_FLOAT_EQ(taa.frame_weight(), 1.0f / float(t + 1)) << "frame " << t;
    EXPECT_EQ(taa.frames_held(), std::uint32_t(t + 1));
    double worst = 0.0;
    for (std::size_t v = 0; v < sum.size(); ++v) {
      sum[v] += double(frames[std::size_t(t)].rgb[v]);
      worst = std::max(worst, std::abs(double(out.rgb[v]) - sum[v] / double(t + 1)));
    }
    EXPECT_LT(worst, 1e-6) << "frame " << t << ": the mean of " << t + 1 << " frames";
  }
  // Past the young history: current_weight, no longer the mean.
  const ImageRgb before = taa.history();
  const ImageRgb& out = taa.accumulate(frames[std::size_t(young)], {8, 4}, test::executor());
  EXPECT_EQ(taa.frame_weight(), o.current_weight);
  double worst = 0.0, from_mean = 0.0;
  for (std::size_t v = 0; v < out.rgb.size(); ++v) {
    const double blend = double(before.rgb[v]) + double(o.current_weight) *
                                                     (double(frames[std::size_t(young)].rgb[v]) - double(before.rgb[v]));
    worst = std::max(worst, std::abs(double(out.rgb[v]) - blend));
    from_mean = std::max(from_mean, std::abs(double(out.rgb[v]) - (sum[v] + double(frames[std::size_t(young)].rgb[v])) /
                                                                        double(young + 1)));
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(from_mean, 1e-4) << "the 11th frame weighs 0.1, not 1/11";
  // A saccade's onset starts a young history again.
  taa.accumulate(frames[0], {8, 4}, test::executor(), /*saccade=*/true);
  EXPECT_TRUE(taa.last_was_reset());
  EXPECT_EQ(taa.frame_weight(), 1.0f);
  taa.accumulate(frames[1], {8, 4}, test::executor(), /*saccade=*/true);
  EXPECT_EQ(taa.frame_weight(), 0.5f);
}

// Without the young mean (the default): the exponential blend from the second
// frame on, so the first frame after a reset fades as (1 - alpha)^k.
TEST_P(Taa, WithoutTheYoungMeanEveryFrameWeighsCurrentWeight) {
  TemporalOptions o;
  o.constraint = GetParam();
  o.mean_while_young = false;
  TemporalAccumulator taa(o);
  const ImageRgb a = checkerboard(9, 7, 0.45f, 0.55f), b = checkerboard(9, 7, 0.0f, 1.0f);
  taa.accumulate(a, {4, 3}, test::executor());
  EXPECT_EQ(taa.frame_weight(), 1.0f);
  const ImageRgb& out = taa.accumulate(b, {4, 3}, test::executor());
  EXPECT_EQ(taa.frame_weight(), o.current_weight);
  for (std::size_t v = 0; v < out.rgb.size(); ++v) {
    EXPECT_NEAR(out.rgb[v], a.rgb[v] + o.current_weight * (b.rgb[v] - a.rgb[v]), 1e-6) << v;
  }
}

TEST(TaaFrameWeight, IsTheMeanThenCurrentWeight) {
  EXPECT_FALSE(TemporalOptions{}.mean_while_young) << "the layer's default blend";
  TemporalOptions o;
  o.mean_while_young = true;
  EXPECT_EQ(temporal_frame_weight(o, 0), 1.0f);  // a reset: the frame alone
  EXPECT_EQ(temporal_frame_weight(o, 1), 0.5f);
  EXPECT_FLOAT_EQ(temporal_frame_weight(o, 3), 0.25f);
  EXPECT_FLOAT_EQ(temporal_frame_weight(o, 9), 0.1f);
  EXPECT_EQ(temporal_frame_weight(o, 10), o.current_weight);
  EXPECT_EQ(temporal_frame_weight(o, 1u << 16), o.current_weight);
  // Frames of 4 rays: their own current_weight, 1 - 0.9^4 = 0.344, from the 2nd frame held on.
  const TemporalOptions four = temporal_options_for_rays(o, 4);
  EXPECT_EQ(temporal_frame_weight(four, 1), 0.5f);
  EXPECT_EQ(temporal_frame_weight(four, 2), four.current_weight);
  o.mean_while_young = false;
  EXPECT_EQ(temporal_frame_weight(o, 0), 1.0f);
  EXPECT_EQ(temporal_frame_weight(o, 1), o.current_weight);
}

TEST_P(Taa, GazeJumpResetsHistory) {
  TemporalOptions o;
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

// accumulate_reprojected: a pixel whose history was rejected (valid 0) is this
// frame exactly; the others blend.
TEST_P(Taa, RejectedHistoryPixelsAreTheCurrentFrameExactly) {
  TemporalOptions o;
  o.constraint = GetParam();
  TemporalAccumulator taa(o);
  const ImageRgb a = gradient(13, 7, 0.0f), b = gradient(13, 7, 0.05f);
  taa.accumulate(a, {6, 3}, test::executor());
  std::vector<std::uint8_t> valid(a.pixel_count(), 1);
  for (std::size_t p = 0; p < valid.size(); p += 3) valid[p] = 0;
  const ImageRgb warped = taa.history();
  const ImageRgb& out = taa.accumulate_reprojected(b, warped, valid, {6, 3}, test::executor());
  ASSERT_FALSE(taa.last_was_reset());
  for (std::size_t p = 0; p < valid.size(); ++p) {
    const bool same = std::memcmp(out.rgb.data() + 3 * p, b.rgb.data() + 3 * p, 3 * sizeof(float)) == 0;
    EXPECT_EQ(same, valid[p] == 0) << "pixel " << p;
  }
}

INSTANTIATE_TEST_SUITE_P(Constraints, Taa, ::testing::Values(HistoryClip::minmax_clamp, HistoryClip::variance_clip),
                         [](const ::testing::TestParamInfo<HistoryClip>& p) {
                           return p.param == HistoryClip::minmax_clamp ? "minmax_clamp" : "variance_clip";
                         });

}  // namespace
}  // namespace foveart::foveation
