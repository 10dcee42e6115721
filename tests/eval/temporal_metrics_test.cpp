// The temporal measure (eval/temporal_metrics.hpp) on synthetic
// sequences whose flicker and error are known in closed form.
#include <eval/temporal_metrics.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

using foveart::metrics::EccentricityMap;
using foveart::foveation::ImageRgb;
using foveart::eval::ReferenceFloor;
using foveart::eval::RingBand;
using foveart::eval::settled_frames;
using foveart::eval::TemporalRing;
using foveart::eval::TemporalError;
using foveart::eval::TemporalRings;
using foveart::eval::TrackedPrevious;

namespace {

constexpr int kTinyW = 4, kTinyH = 2;

// Rings by hand: the left half in ring 0, the right half in `right_ring`.
EccentricityMap map_with(std::uint8_t right_ring) {
  EccentricityMap m;
  m.width_px = kTinyW;
  m.height_px = kTinyH;
  m.ring.resize(kTinyW * kTinyH);
  for (int y = 0; y < kTinyH; ++y)
    for (int x = 0; x < kTinyW; ++x) m.ring[std::size_t(y * kTinyW + x)] = x < kTinyW / 2 ? 0 : right_ring;
  for (std::uint8_t r : m.ring) ++m.ring_pixels[r];
  return m;
}

// The reference of frame t: a ramp that moves (the truth changes by 0.01 per frame and pixel index).
ImageRgb truth(int t) {
  ImageRgb im(kTinyW, kTinyH);
  for (std::size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = 0.2f + 0.01f * float(t) * float(i % 7) + 0.02f * float(i % 3);
  return im;
}

ImageRgb plus(const ImageRgb& a, float v) {
  ImageRgb out = a;
  for (float& x : out.rgb) x += v;
  return out;
}

}  // namespace

TEST(TemporalMetrics, FollowingTheTruthExactlyHasNoFlickerAndNoError) {
  TemporalError e;
  const EccentricityMap m = map_with(4);
  for (int t = 0; t < 5; ++t) e.add_frame(truth(t), truth(t), m);
  const TemporalRings r = e.rings();
  EXPECT_EQ(e.frames(), 5);
  // The truth itself changes from frame to frame; none of that counts as flicker.
  EXPECT_DOUBLE_EQ(r[0].flicker_rms, 0.0);
  EXPECT_DOUBLE_EQ(r[4].flicker_rms, 0.0);
  EXPECT_DOUBLE_EQ(r[0].error_mse, 0.0);
  EXPECT_EQ(r[0].frame_values, 5u * 4u * 3u);
  EXPECT_EQ(r[0].pair_values, 4u * 4u * 3u);
  EXPECT_TRUE(std::isnan(r[2].flicker_rms));  // an empty ring
  EXPECT_TRUE(std::isnan(r[2].error_mse));
}

TEST(TemporalMetrics, ConstantOffsetIsErrorWithoutFlicker) {
  TemporalError e;
  const EccentricityMap m = map_with(5);
  for (int t = 0; t < 4; ++t) e.add_frame(plus(truth(t), 0.1f), truth(t), m);
  const TemporalRings r = e.rings();
  EXPECT_NEAR(r[0].flicker_rms, 0.0, 1e-7);
  EXPECT_NEAR(std::sqrt(r[0].error_mse), 0.1, 1e-6);
  EXPECT_NEAR(r[5].psnr_db(), 20.0, 1e-4);  // 10 log10(1 / 0.01)
}

TEST(TemporalMetrics, AlternatingNoiseFlickersTwiceItsAmplitude) {
  // I_t = R_t +- a, the sign alternating every frame: every pair differs by 2a beyond the truth.
  TemporalError e;
  const EccentricityMap m = map_with(6);
  const float a = 0.05f;
  for (int t = 0; t < 6; ++t) e.add_frame(plus(truth(t), t % 2 ? a : -a), truth(t), m);
  const TemporalRings r = e.rings();
  EXPECT_NEAR(r[0].flicker_rms, 2.0 * double(a), 1e-6);
  EXPECT_NEAR(r[6].flicker_rms, 2.0 * double(a), 1e-6);
  EXPECT_NEAR(std::sqrt(r[0].error_mse), double(a), 1e-6);
}

TEST(TemporalMetrics, GhostingOfAUniformMotionIsErrorNotFlicker) {
  // I_t = R_{t-1} (one frame late): the error is the truth's change, but a
  // uniformly moving truth changes by the same amount each frame, so the
  // frame-to-frame change matches the truth's and there is no flicker after
  // the first pair (I_0 = R_0).
  TemporalError e;
  const EccentricityMap m = map_with(3);
  for (int t = 0; t < 5; ++t) e.add_frame(truth(t == 0 ? 0 : t - 1), truth(t), m);
  const TemporalRings r = e.rings();
  // Pair (0, 1): I changes by 0, R by d; pairs (1,2)...(3,4): both by d. Frame 0 has no error.
  const ImageRgb d0 = truth(0), d1 = truth(1);
  double d2_left = 0.0, d2_right = 0.0;
  for (int y = 0; y < kTinyH; ++y)
    for (int x = 0; x < kTinyW; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::size_t k = std::size_t((y * kTinyW + x) * 3 + c);
        const double d = double(d1.rgb[k]) - double(d0.rgb[k]);
        (x < kTinyW / 2 ? d2_left : d2_right) += d * d;
      }
  // Flicker: only pair (0, 1) contributes, sum d^2 over 4 pairs' values. Error: frames 1-4 each d^2.
  EXPECT_NEAR(r[0].flicker_rms, std::sqrt(d2_left / (4.0 * 12.0)), 1e-6);
  EXPECT_NEAR(r[0].error_mse, 4.0 * d2_left / (5.0 * 12.0), 1e-7);
  EXPECT_NEAR(r[3].error_mse, 4.0 * d2_right / (5.0 * 12.0), 1e-7);
  EXPECT_GT(r[0].error_mse, 0.0);
}

TEST(TemporalMetrics, EachFramesOwnRingsCount) {
  // The gaze moves: frame 1's right half is ring 2, frame 0's ring 1. Frame 1's
  // pair goes to frame 1's rings.
  TemporalError e;
  e.add_frame(plus(truth(0), 0.1f), truth(0), map_with(1));
  e.add_frame(plus(truth(1), -0.1f), truth(1), map_with(2));
  const TemporalRings r = e.rings();
  EXPECT_EQ(r[1].frame_values, 12u);
  EXPECT_EQ(r[1].pair_values, 0u);
  EXPECT_TRUE(std::isnan(r[1].flicker_rms));
  EXPECT_EQ(r[2].pair_values, 12u);
  EXPECT_NEAR(r[2].flicker_rms, 0.2, 1e-6);
}

TEST(TemporalMetrics, PooledOverRingsAndFramesWeighsEveryValueOnce) {
  // Frames 0-3 carry an offset of 0.1, 0.3, 0.1, 0.3 on the left (ring 0) and
  // 0.2 everywhere on the right (ring 4): pairs change by 0.2 on the left, 0 on
  // the right.
  TemporalError e;
  const EccentricityMap m = map_with(4);
  for (int t = 0; t < 4; ++t) {
    ImageRgb image = truth(t);
    for (int y = 0; y < kTinyH; ++y)
      for (int x = 0; x < kTinyW; ++x)
        for (int c = 0; c < 3; ++c) image.at(x, y)[c] += x < kTinyW / 2 ? (t % 2 ? 0.3f : 0.1f) : 0.2f;
    e.add_frame(image, truth(t), m);
  }
  const TemporalRings rings = e.rings();
  // Both rings pooled: half the pair values change by 0.2, half by 0 -> RMS 0.2 / sqrt(2).
  const TemporalRing both = e.pooled(RingBand{"both", 0, 5});
  EXPECT_EQ(both.pair_values, rings[0].pair_values + rings[4].pair_values);
  EXPECT_EQ(both.frame_values, 4u * 8u * 3u);
  EXPECT_NEAR(both.flicker_rms, 0.2 / std::sqrt(2.0), 1e-6);
  // Error: left 0.01 and 0.09 alternately (mean 0.05), right 0.04 -> 0.045.
  EXPECT_NEAR(both.error_mse, 0.045, 1e-6);
  // A band of one ring is that ring.
  EXPECT_DOUBLE_EQ(e.pooled(RingBand{"ring", 4, 5}).error_mse, rings[4].error_mse);
  // Frame by frame: frame 0 has no pair; frame 1 is 0.1 and 0.3 on the left.
  const std::vector<TemporalRing> frames = e.by_frame(RingBand{"left", 0, 1});
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_TRUE(std::isnan(frames[0].flicker_rms));
  EXPECT_NEAR(frames[0].error_mse, 0.01, 1e-7);
  EXPECT_NEAR(frames[1].flicker_rms, 0.2, 1e-6);
  EXPECT_NEAR(frames[1].error_mse, 0.09, 1e-6);
  // A frame mask keeps only its frames: frames 1 and 3 have error 0.09, their pairs 0.2.
  const std::vector<std::uint8_t> odd = {0, 1, 0, 1};
  const TemporalRing masked = e.pooled(RingBand{"left", 0, 1}, &odd);
  EXPECT_NEAR(masked.error_mse, 0.09, 1e-6);
  EXPECT_EQ(masked.pair_values, 2u * 4u * 3u);
  EXPECT_NEAR(masked.flicker_rms, 0.2, 1e-6);
  // A band outside the rings or a mask of the wrong length is an error.
  EXPECT_THROW(e.pooled(RingBand{"none", 2, 2}), std::invalid_argument);
  EXPECT_THROW(e.pooled(RingBand{"beyond", 6, 8}), std::invalid_argument);
  const std::vector<std::uint8_t> short_mask = {1, 1};
  EXPECT_THROW(e.pooled(RingBand{"left", 0, 1}, &short_mask), std::invalid_argument);
}

TEST(TemporalMetrics, SettledFramesCountFromTheLastRestart) {
  //                                 0  1  2  3  4  5  6  7  8  9
  const std::vector<std::uint8_t> restart = {0, 0, 0, 0, 1, 1, 0, 0, 0, 0};
  // Frame 0 restarts; 2 frames after it (2, 3) settle; frames 4-5 restart again; 7 on settle.
  EXPECT_EQ(settled_frames(restart, 2), (std::vector<std::uint8_t>{0, 0, 1, 1, 0, 0, 0, 1, 1, 1}));
  // Zero frames: every frame but a restarting one.
  EXPECT_EQ(settled_frames(restart, 0), (std::vector<std::uint8_t>{0, 1, 1, 1, 0, 0, 1, 1, 1, 1}));
  // Longer than the sequence: none.
  EXPECT_EQ(settled_frames(restart, 10), std::vector<std::uint8_t>(10, 0));
  EXPECT_TRUE(settled_frames({}, 3).empty());
}

TEST(TemporalMetrics, MismatchedSizesThrow) {
  TemporalError e;
  EXPECT_THROW(e.add_frame(ImageRgb(3, 2), ImageRgb(3, 2), map_with(1)), std::invalid_argument);
  EXPECT_THROW(e.add_frame(truth(0), ImageRgb(3, 2), map_with(1)), std::invalid_argument);
  ReferenceFloor f;
  EXPECT_THROW(f.add_frame(std::vector<float>(3), map_with(1)), std::invalid_argument);
}

namespace {

// A map for the CSF-weighted measure: every pixel at `ecc_deg` in ring 0, 60 pixels per degree, so
// that the finest band (30 cycles/degree, the display's Nyquist) is one the fovea resolves (< 39.2).
EccentricityMap csf_map(int w, int h, float ecc_deg) {
  EccentricityMap m;
  m.width_px = w;
  m.height_px = h;
  m.ring.assign(std::size_t(w * h), 0);
  m.eccentricity_deg.assign(std::size_t(w * h), ecc_deg);
  m.pixels_per_deg.assign(std::size_t(w * h), 60.0f);
  m.ring_pixels[0] = std::uint64_t(w * h);
  return m;
}

// A grey image of value v, plus `checker` * (+1, -1, ...) in a pixel checkerboard.
ImageRgb grey(int w, int h, float v, float checker = 0.0f) {
  ImageRgb im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) im.at(x, y)[c] = v + ((x + y) % 2 == 0 ? checker : -checker);
  return im;
}

}  // namespace

TEST(TemporalMetrics, CsfFlickerAtTheGazeIsTheLumaChange) {
  // Where the eye resolves every band the weighting telescopes back to the luma change: +-a alternating is 2a.
  TemporalError e;
  const EccentricityMap m = csf_map(16, 16, 0.0f);
  for (int t = 0; t < 4; ++t) e.add_frame(grey(16, 16, t % 2 == 0 ? 0.53f : 0.47f), grey(16, 16, 0.5f), m);
  const TemporalRings r = e.rings();
  EXPECT_NEAR(r[0].flicker_csf_rms, 0.06, 1e-6);
  EXPECT_NEAR(r[0].flicker_csf_rms, r[0].flicker_rms, 1e-6);
  EXPECT_EQ(r[0].csf_pair_pixels, 3u * 16u * 16u);
}

TEST(TemporalMetrics, CsfFlickerFadesFinerThanThePeripheryResolves) {
  // At 40 degrees the eye resolves up to 2.13 cycles/degree (thesis eq. 2): a uniform change keeps the
  // low-pass band's weight exp(-alpha f e / e2) at f = 60 / 64 cycles/degree; a pixel checkerboard
  // flickering as strongly is almost all beyond the cut-off.
  TemporalError uniform, checker;
  const EccentricityMap m = csf_map(32, 32, 40.0f);
  for (int t = 0; t < 3; ++t) {
    const float a = t % 2 == 0 ? 0.03f : -0.03f;
    uniform.add_frame(grey(32, 32, 0.5f + a), grey(32, 32, 0.5f), m);
    checker.add_frame(grey(32, 32, 0.5f, a), grey(32, 32, 0.5f), m);
  }
  const double low_pass_weight = std::exp(-0.106 * (60.0 / 64.0) * 40.0 / 2.3);
  EXPECT_NEAR(uniform.rings()[0].flicker_csf_rms, 0.06 * low_pass_weight, 1e-6);
  EXPECT_NEAR(checker.rings()[0].flicker_rms, 0.06, 1e-6) << "the same change at fixed pixels";
  EXPECT_LT(checker.rings()[0].flicker_csf_rms, 0.05 * uniform.rings()[0].flicker_csf_rms);
}

TEST(TemporalMetrics, CsfFlickerNeedsTheMapsEccentricities) {
  TemporalError e;
  const EccentricityMap m = map_with(4);  // rings only
  for (int t = 0; t < 3; ++t) e.add_frame(plus(truth(t), t % 2 == 0 ? 0.1f : 0.0f), truth(t), m);
  EXPECT_GT(e.rings()[0].flicker_rms, 0.0);
  EXPECT_TRUE(std::isnan(e.rings()[0].flicker_csf_rms));
  EXPECT_EQ(e.rings()[0].csf_pair_pixels, 0u);
}

TEST(TemporalMetrics, ReferenceFloorWeighsBothFramesHalfDifferencesUnderThisFramesMap) {
  // At the gaze the weighting is the identity on luma: r_t = d_t / 2, floor^2 = (d_t / 2)^2 + (d_{t-1} / 2)^2.
  const EccentricityMap m = csf_map(8, 8, 0.0f);
  const std::vector<float> residual(64, 0.0f), d1(64, 0.02f), d2(64, -0.04f);
  ReferenceFloor f;
  f.add_frame(residual, m, &d1);
  f.add_frame(residual, m, &d2);
  const TemporalRings r = f.rings();
  EXPECT_NEAR(r[0].flicker_csf_rms, std::sqrt(0.01 * 0.01 + 0.02 * 0.02), 1e-7);
  EXPECT_EQ(r[0].csf_pair_pixels, 64u);
  // A frame without its signed difference leaves the weighted floor unknown, not too low.
  ReferenceFloor g;
  g.add_frame(residual, m, &d1);
  g.add_frame(residual, m);
  g.add_frame(residual, m, &d2);
  EXPECT_TRUE(std::isnan(g.rings()[0].flicker_csf_rms));
  const std::vector<float> short_difference(3, 0.0f);
  EXPECT_THROW(g.add_frame(residual, m, &short_difference), std::invalid_argument);
}

TEST(TemporalMetrics, ReferenceFloorAddsTheVariancesOfConsecutiveFrames) {
  ReferenceFloor f;
  const EccentricityMap m = map_with(4);
  f.add_frame(std::vector<float>(kTinyW * kTinyH, 0.01f), m);
  f.add_frame(std::vector<float>(kTinyW * kTinyH, 0.03f), m);
  f.add_frame(std::vector<float>(kTinyW * kTinyH, 0.01f), m);
  const TemporalRings r = f.rings();
  // Pairs: 0.01 + 0.03 and 0.03 + 0.01 -> mean 0.04; error: mean of 0.01, 0.03, 0.01.
  EXPECT_NEAR(r[0].flicker_rms, std::sqrt(0.04), 1e-7);
  EXPECT_EQ(r[0].flicker_tracked_rms, r[0].flicker_rms) << "the bound for the flicker along the motion";
  EXPECT_NEAR(r[4].error_mse, 0.05 / 3.0, 1e-8);
  EXPECT_EQ(r[4].frame_values, 3u * 4u * 3u);
}

namespace {

// A row pattern that moves one pixel right per frame: the truth at frame t, pixel x.
float content(int x, int t) { return 0.5f + 0.3f * std::sin(1.7f * float(x - t)); }
// An error pattern as a function of position.
float blemish(int x) { return 0.05f * float((x * 5) % 3) - 0.05f; }

// Frame t of a kTinyW x kTinyH sequence; image = truth + the error at screen x (fixed) or
// at content position x - t (carried along by the motion).
ImageRgb moving(int t, bool with_error, bool error_moves) {
  ImageRgb im(kTinyW, kTinyH);
  for (int y = 0; y < kTinyH; ++y)
    for (int x = 0; x < kTinyW; ++x)
      for (int c = 0; c < 3; ++c)
        im.at(x, y)[c] = content(x, t) + (with_error ? blemish(error_moves ? x - t + 8 : x) : 0.0f);
  return im;
}

// The previous error warped one pixel right (the exact motion): pixel x came from x - 1;
// the first column was off-screen.
void warp_right(const ImageRgb& previous_error, ImageRgb* warped, std::vector<std::uint8_t>* valid) {
  *warped = ImageRgb(kTinyW, kTinyH);
  valid->assign(std::size_t(kTinyW * kTinyH), 0);
  for (int y = 0; y < kTinyH; ++y)
    for (int x = 1; x < kTinyW; ++x) {
      std::copy_n(previous_error.at(x - 1, y), 3, warped->at(x, y));
      (*valid)[std::size_t(y * kTinyW + x)] = 1;
    }
}

TemporalRings run_moving(bool error_moves) {
  TemporalError e;
  const EccentricityMap m = map_with(5);
  ImageRgb warped;
  std::vector<std::uint8_t> valid;
  for (int t = 0; t < 4; ++t) {
    TrackedPrevious tracked;
    if (t > 0) {
      warp_right(e.previous_error(), &warped, &valid);
      tracked = {&warped, &valid};
    }
    e.add_frame(moving(t, true, error_moves), moving(t, false, false), m, &tracked);
  }
  return e.rings();
}

}  // namespace

TEST(TemporalMetrics, AnErrorCarriedByTheMotionIsNoTrackedFlicker) {
  // A blemish that moves with the content (a soft edge, a constant offset of a
  // surface): it changes at every fixed pixel, not along the motion.
  const TemporalRings r = run_moving(/*error_moves=*/true);
  EXPECT_GT(r[0].flicker_rms, 0.03);
  EXPECT_NEAR(r[0].flicker_tracked_rms, 0.0, 1e-7);
  EXPECT_EQ(r[0].tracked_pair_values, 3u * 2u * 3u) << "3 pairs x 2 rows x the one left-half column that was in view x 3 channels";
}

TEST(TemporalMetrics, AnErrorFixedOnTheScreenIsTrackedFlickerWhileTheContentMoves) {
  // A blemish fixed on the screen while the content slides under it (sparse or
  // fixed samples): no change at a fixed pixel, a change along the motion of
  // blemish(x) - blemish(x - 1).
  const TemporalRings r = run_moving(/*error_moves=*/false);
  EXPECT_NEAR(r[0].flicker_rms, 0.0, 1e-7);
  double sum = 0.0;
  int n = 0;
  for (int x = 1; x < kTinyW / 2; ++x, ++n) sum += std::pow(double(blemish(x)) - double(blemish(x - 1)), 2.0);
  EXPECT_NEAR(r[0].flicker_tracked_rms, std::sqrt(sum / double(n)), 1e-6);
  EXPECT_GT(r[0].flicker_tracked_rms, 0.03);
}

TEST(TemporalMetrics, TrackedPreviousOfAnotherSizeThrows) {
  TemporalError e;
  const EccentricityMap m = map_with(1);
  e.add_frame(truth(0), truth(0), m);
  const ImageRgb small(3, 2);
  std::vector<std::uint8_t> valid(kTinyW * kTinyH, 1);
  const TrackedPrevious bad_image{&small, &valid};
  EXPECT_THROW(e.add_frame(truth(1), truth(1), m, &bad_image), std::invalid_argument);
  const ImageRgb right(kTinyW, kTinyH);
  std::vector<std::uint8_t> short_valid(3, 1);
  const TrackedPrevious bad_valid{&right, &short_valid};
  EXPECT_THROW(e.add_frame(truth(1), truth(1), m, &bad_valid), std::invalid_argument);
}

TEST(TemporalMetrics, BinomialBlurKeepsFlatImagesAndSpreadsAnImpulse) {
  ImageRgb flat(5, 5);
  for (float& v : flat.rgb) v = 0.25f;
  ImageRgb out;
  foveart::eval::binomial_blur_3x3(flat, &out);
  for (float v : out.rgb) EXPECT_FLOAT_EQ(v, 0.25f);
  ImageRgb impulse(5, 5);
  impulse.at(2, 2)[1] = 16.0f;
  foveart::eval::binomial_blur_3x3(impulse, &out);
  const float kernel[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
  double total = 0.0;
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      const bool inside = std::abs(x - 2) <= 1 && std::abs(y - 2) <= 1;
      EXPECT_FLOAT_EQ(out.at(x, y)[1], inside ? kernel[y - 1][x - 1] : 0.0f) << x << "," << y;
      EXPECT_FLOAT_EQ(out.at(x, y)[0], 0.0f);
      total += double(out.at(x, y)[1]);
    }
  EXPECT_DOUBLE_EQ(total, 16.0);
}

// An image history that is exact but for its noise: the exponential blend with
// weight alpha of 1-ray frames whose errors are independent per pixel and
// frame, carried one pixel a frame by the motion (exact reprojection). At a
// fixed pixel consecutive frames then hold different surfaces' errors, so the
// history flickers as much as an error of its variance v = alpha / (2 - alpha)
// drawn anew each frame, sqrt(2 v): against 1-ray frames, sqrt(2), only
// sqrt((2 - alpha) / alpha) = sqrt(19) = 4.36x less at alpha 0.1. Along the
// motion it changes by alpha (n_t - e_{t-1}) alone: sqrt(2 / (alpha^2 (1 + v)))
// = 13.8x less (docs/pricelist.md, "What any image history reaches").
TEST(TemporalMetrics, AnExactHistoryCarriedByTheMotionFlickersAtFixedPixelsAsItsErrorDrawnAnew) {
  constexpr int kWide = 192, kTall = 96, kFrames = 40;
  constexpr double kAlpha = 0.1, kSigma = 0.05;
  EccentricityMap m;
  m.width_px = kWide;
  m.height_px = kTall;
  m.ring.assign(std::size_t(kWide * kTall), 0);
  m.ring_pixels[0] = std::uint64_t(kWide * kTall);
  ImageRgb truth_image(kWide, kTall);
  std::fill(truth_image.rgb.begin(), truth_image.rgb.end(), 0.5f);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, kSigma);
  const double v = kAlpha / (2.0 - kAlpha);  // the blend's variance in units of one frame's
  // The history's error e, stationary from the start; each frame carries it one pixel right.
  std::vector<double> e(truth_image.rgb.size());
  for (double& x : e) x = std::sqrt(v) * noise(rng);
  auto carried = [&](const std::vector<double>& field) {
    std::vector<double> out(field.size());
    for (int y = 0; y < kTall; ++y)
      for (int x = 0; x < kWide; ++x)
        for (int c = 0; c < 3; ++c)
          out[std::size_t((y * kWide + x) * 3 + c)] = field[std::size_t((y * kWide + (x + kWide - 1) % kWide) * 3 + c)];
    return out;
  };
  auto image_of = [&](const std::vector<double>& error) {
    ImageRgb im = truth_image;
    for (std::size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] += float(error[i]);
    return im;
  };
  TemporalError history, one_ray;
  const std::vector<std::uint8_t> valid(std::size_t(kWide * kTall), 1);
  for (int t = 0; t < kFrames; ++t) {
    std::vector<double> fresh(e.size()), alone(e.size());
    for (double& x : fresh) x = noise(rng);
    for (double& x : alone) x = noise(rng);
    const std::vector<double> previous = carried(e);
    for (std::size_t i = 0; i < e.size(); ++i) e[i] = (1.0 - kAlpha) * previous[i] + kAlpha * fresh[i];
    // Along the motion: the last error carried as the image was (exact reprojection).
    std::vector<double> last_error(e.size());
    if (t > 0) {
      for (std::size_t i = 0; i < e.size(); ++i) last_error[i] = double(history.previous_error().rgb[i]);
    }
    const ImageRgb warped = image_of(carried(last_error));
    ImageRgb warped_error = warped;
    for (float& x : warped_error.rgb) x -= 0.5f;
    const TrackedPrevious tracked{&warped_error, &valid};
    history.add_frame(image_of(e), truth_image, m, t > 0 ? &tracked : nullptr);
    one_ray.add_frame(image_of(alone), truth_image, m);
  }
  const TemporalRing h = history.rings()[0], o = one_ray.rings()[0];
  EXPECT_NEAR(o.flicker_rms, std::sqrt(2.0) * kSigma, 0.01 * kSigma);
  EXPECT_NEAR(o.flicker_rms / h.flicker_rms, std::sqrt((2.0 - kAlpha) / kAlpha), 0.02 * std::sqrt(19.0));
  const double along = std::sqrt(2.0 / (kAlpha * kAlpha * (1.0 + v)));
  EXPECT_NEAR(o.flicker_rms / h.flicker_tracked_rms, along, 0.03 * along);
  EXPECT_LT(o.flicker_rms / h.flicker_rms, 5.0) << "5x at fixed pixels asks alpha <= 2/26 of an exact history";
}
