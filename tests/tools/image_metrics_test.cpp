// Image metrics (metrics/image_metrics.hpp, csf_error.hpp): known answers.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include <metrics/csf_error.hpp>
#include "foveation/eye_rays.hpp"
#include <metrics/image_metrics.hpp>

namespace foveart::metrics {
namespace {

using foveation::EyePose;
using foveation::ImageRgb;
using foveation::make_eye_view;

ImageRgb gradient(int w, int h) {
  ImageRgb im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = im.at(x, y);
      p[0] = 0.2f + 0.6f * float(x) / float(w);
      p[1] = 0.3f + 0.4f * float(y) / float(h);
      p[2] = 0.5f;
    }
  return im;
}

ImageRgb noisy(const ImageRgb& base, std::mt19937& rng, float sigma) {
  std::normal_distribution<float> n(0.0f, sigma);
  ImageRgb out = base;
  for (float& v : out.rgb) v += n(rng);
  return out;
}

// A symmetric pinhole view `distance_px` pixels from the eye.
FoveartEyeView pinhole(int w, int h, double distance_px) {
  const float hx = float(std::atan(0.5 * w / distance_px)), hy = float(std::atan(0.5 * h / distance_px));
  return make_eye_view(0, std::uint32_t(w), std::uint32_t(h), EyePose{}, -hx, hx, hy, -hy);
}

TEST(ImageMetrics, PsnrOfKnownError) {
  const auto a = gradient(16, 16);
  auto b = a;
  EXPECT_TRUE(std::isinf(psnr(a, b)));
  for (float& v : b.rgb) v += 0.1f;
  EXPECT_NEAR(psnr(a, b), 20.0, 1e-4);
  EXPECT_NEAR(psnr_of_mse(0.01), 20.0, 1e-12);
  EXPECT_NEAR(mean_abs_difference(a, b), 0.1, 1e-6);
  EXPECT_THROW(psnr(a, gradient(8, 8)), std::invalid_argument);
}

TEST(ImageMetrics, SsimIsOneForIdenticalAndLowerForNoise) {
  const auto a = gradient(40, 30);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-9);
  std::mt19937 rng(2);
  const auto b = noisy(a, rng, 0.1f);
  const double s = ssim(a, b);
  EXPECT_LT(s, 0.9);
  EXPECT_GT(s, -1.0);
}

TEST(ImageMetrics, DisplayEncodeIsSrgbOfClampedLinear) {
  ImageRgb im(1, 1);
  im.rgb = {-0.5f, 0.18f, 4.0f};
  const ImageRgb e = display_encode(im);
  EXPECT_EQ(e.rgb[0], 0.0f);
  EXPECT_NEAR(e.rgb[1], 0.4614, 1e-3);  // sRGB of 18 % grey
  EXPECT_NEAR(e.rgb[2], 1.0f, 1e-6f);
}

TEST(EccentricityMap, SymmetricPinholeIsAtanOfDistanceOverViewDistance) {
  const int w = 400, h = 300;
  const double distance = 200.0;
  const auto map = eccentricity_map(pinhole(w, h, distance), {200.0f, 150.0f});
  for (auto [x, y] : {std::pair{200, 150}, {260, 150}, {10, 20}, {399, 299}}) {
    const double d = std::hypot(x + 0.5 - 200.0, y + 0.5 - 150.0);
    EXPECT_NEAR(map.eccentricity_deg[std::size_t(y) * w + std::size_t(x)], std::atan(d / distance) * 180.0 / std::numbers::pi, 1e-3)
        << x << "," << y;
  }
  // Pixels per degree at the centre: D * pi / 180 (thesis eq. 3 is half of it).
  EXPECT_NEAR(map.pixels_per_deg[150 * w + 200], distance * std::numbers::pi / 180.0, 0.01);
  std::uint64_t total = 0;
  for (auto n : map.ring_pixels) total += n;
  EXPECT_EQ(total, std::uint64_t(w) * h);
}

TEST(EccentricityMap, AsymmetricFrustumUsesTheRayAngle) {
  // A frustum 10 deg to the left and 40 deg to the right: the gaze at the
  // optical axis (not the image centre) has eccentricity 0 and a pixel at the
  // right edge 40 deg, whatever atan(d / D) about the image centre would say.
  const int w = 500, h = 100;
  const float l = float(-10.0 * std::numbers::pi / 180.0), r = float(40.0 * std::numbers::pi / 180.0);
  const float v = float(std::atan(std::tan(double(r)) * 0.5 * h / w * (1.0 + std::tan(10.0 * std::numbers::pi / 180.0) / std::tan(double(r)))));
  const auto view = make_eye_view(0, w, h, EyePose{}, l, r, v, -v);
  const float axis_x = float(w * std::tan(10.0 * std::numbers::pi / 180.0) / (std::tan(10.0 * std::numbers::pi / 180.0) + std::tan(double(r))));
  const auto map = eccentricity_map(view, {axis_x, 50.0f});
  EXPECT_NEAR(map.eccentricity_deg[50 * w + (w - 1)], 40.0, 0.1);
  EXPECT_NEAR(map.eccentricity_deg[50 * w + 0], 10.0, 0.1);
  EXPECT_EQ(map.ring[50 * w + (w - 1)], 5);  // 30-45
}

TEST(RingMetrics, ErrorOnlyBeyondThirtyDegreesLandsInTheOuterRings) {
  const int w = 400, h = 300;
  const auto ref = gradient(w, h);
  auto im = ref;
  const auto map = eccentricity_map(pinhole(w, h, 200.0), {200, 150});
  for (std::size_t i = 0; i < map.ring.size(); ++i)
    if (map.eccentricity_deg[i] > 32.0f) im.rgb[i * 3] += 0.2f;
  const auto c = compare_images(ref, im, map);
  ASSERT_EQ(c.rings.size(), kRingCount);
  EXPECT_EQ(c.rings[0].from_deg, 0.0);
  EXPECT_EQ(c.rings[0].to_deg, 2.5);
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_TRUE(std::isinf(c.rings[r].psnr)) << r;
    EXPECT_EQ(c.rings[r].csf_rmse, 0.0) << r;
  }
  EXPECT_TRUE(std::isfinite(c.rings[5].psnr));
  EXPECT_LT(c.rings[5].ssim, 1.0);
  EXPECT_GT(c.rings[5].csf_rmse, 0.0);
  // Ring MSE is the plain mean over the ring's pixels and channels.
  const auto mse = ring_mse(ref, im, map);
  double se = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < map.ring.size(); ++i)
    if (map.ring[i] == 5) {
      for (int ch = 0; ch < 3; ++ch) se += std::pow(double(im.rgb[i * 3 + ch]) - double(ref.rgb[i * 3 + ch]), 2.0);
      ++n;
    }
  EXPECT_NEAR(mse[5], se / double(3 * n), 1e-12);
  EXPECT_EQ(c.rings[5].pixels, n);
}

TEST(CsfWeight, IsOneAtTheGazeAndFadesWithEccentricityAndFrequency) {
  EXPECT_DOUBLE_EQ(csf_weight(5.0, 0.0, 100.0), 1.0);
  // Cut-off at the gaze: e2 ln 64 / (e2 alpha) = 39.2 cycles/degree (thesis eq. 2).
  EXPECT_GT(csf_weight(39.0, 0.0, 1000.0), 0.0);
  EXPECT_EQ(csf_weight(39.5, 0.0, 1000.0), 0.0);
  // The display's limit (eq. 3): half the pixels per degree.
  EXPECT_GT(csf_weight(6.0, 0.0, 12.0), 0.0);
  EXPECT_EQ(csf_weight(6.1, 0.0, 12.0), 0.0);
  double last = 1.0;
  for (double e : {1.0, 2.5, 5.0, 10.0, 20.0}) {
    const double wgt = csf_weight(1.0, e, 30.0);
    EXPECT_LT(wgt, last) << e;
    last = wgt;
  }
  EXPECT_NEAR(csf_weight(2.0, 10.0, 30.0), std::exp(-0.106 * 2.0 * 10.0 / 2.3), 1e-12);
}

TEST(CsfError, IdenticalImagesHaveZeroError) {
  const auto a = gradient(120, 90);
  const auto map = eccentricity_map(pinhole(120, 90, 100.0), {60, 45});
  for (float e : csf_error_map(a, a, map)) ASSERT_EQ(e, 0.0f);
  const auto c = compare_images(a, a, map);
  EXPECT_EQ(c.csf_rmse, 0.0);
  EXPECT_TRUE(std::isinf(c.rings[0].csf_psnr));
}

TEST(CsfError, AUniformShiftAtTheGazeIsThePlainLumaError) {
  // Every band of a constant difference is zero but the low-pass, whose
  // frequency (ppd / 64) has weight ~1 near the gaze: the bands telescope to d.
  const auto a = gradient(64, 64);
  auto b = a;
  for (float& v : b.rgb) v += 0.1f;
  const auto map = eccentricity_map(pinhole(64, 64, 2000.0), {32, 32});
  const auto err = csf_error_map(a, b, map);
  EXPECT_NEAR(err[32 * 64 + 32], 0.1, 1e-4);
}

TEST(CsfError, WeighsALumaDifferenceAsTheImagesThatDifferByIt) {
  // csf_error_map is the weighting of the images' luma difference; a map without eccentricities is refused.
  const auto a = gradient(48, 40);
  auto b = a;  // a ripple of every scale, differing per channel
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) b.at(x, y)[c] += 0.05f * std::sin(0.3f * float(x * (c + 1)) + 0.7f * float(y));
  const auto map = eccentricity_map(pinhole(48, 40, 60.0), {10, 30});
  std::vector<double> d(48 * 40);
  for (std::size_t i = 0; i < d.size(); ++i) {
    const float* p = b.rgb.data() + i * 3;
    const float* q = a.rgb.data() + i * 3;
    d[i] = rec601_luma(double(p[0]) - double(q[0]), double(p[1]) - double(q[1]), double(p[2]) - double(q[2]));
  }
  const std::vector<float> weighted = csf_weighted_luma(d, map);
  EXPECT_EQ(weighted, csf_error_map(a, b, map));
  EXPECT_GT(*std::max_element(weighted.begin(), weighted.end()), 0.0f);
  d.pop_back();
  EXPECT_THROW(csf_weighted_luma(d, map), std::invalid_argument);
  auto bare = map;
  bare.pixels_per_deg.clear();
  EXPECT_THROW(csf_error_map(a, a, bare), std::invalid_argument);
}

TEST(CsfError, GrowsMonotonicallyWithNoiseAmplitude) {
  const int w = 160, h = 120;
  const auto a = gradient(w, h);
  const auto map = eccentricity_map(pinhole(w, h, 150.0), {80, 60});
  std::vector<double> last(kRingCount, 0.0);
  for (float sigma : {0.005f, 0.01f, 0.02f, 0.05f}) {
    std::mt19937 rng(7);  // the same noise pattern, scaled
    const auto c = compare_images(a, noisy(a, rng, sigma), map);
    for (std::size_t r = 0; r < kRingCount; ++r) {
      if (c.rings[r].pixels == 0) continue;
      EXPECT_GT(c.rings[r].csf_rmse, last[r]) << "ring " << r << " sigma " << sigma;
      last[r] = c.rings[r].csf_rmse;
    }
  }
}

TEST(CsfError, TheSameDifferenceWeighsLessInThePeripheryThanAtTheGaze) {
  // A 16x16 patch of fine noise, once at the gaze, once 30 degrees away.
  const int w = 800, h = 200;
  const double distance = 400.0;  // 7 px per degree at the centre
  const auto a = gradient(w, h);
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0f, 0.05f);
  std::vector<float> patch(16 * 16);
  for (float& v : patch) v = n(rng);
  const auto with_patch = [&](int cx, int cy) {
    ImageRgb b = a;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        for (int ch = 0; ch < 3; ++ch) b.at(cx - 8 + x, cy - 8 + y)[ch] += patch[std::size_t(y * 16 + x)];
    return b;
  };
  const auto map = eccentricity_map(pinhole(w, h, distance), {100, 100});
  const int far_x = 100 + int(std::lround(distance * std::tan(30.0 * std::numbers::pi / 180.0)));
  const auto sum_sq = [&](const ImageRgb& b) {
    double s = 0.0;
    for (float e : csf_error_map(a, b, map)) s += double(e) * double(e);
    return s;
  };
  const double fovea = sum_sq(with_patch(100, 100));
  const double periphery = sum_sq(with_patch(far_x, 100));
  EXPECT_GT(fovea, 0.0);
  EXPECT_GT(periphery, 0.0);  // a shift of the patch's mean still shows
  EXPECT_LT(periphery, 0.25 * fovea);
  // Plain squared error cannot tell them apart.
  EXPECT_NEAR(std::pow(psnr(a, with_patch(100, 100)) - psnr(a, with_patch(far_x, 100)), 2.0), 0.0, 1e-6);
}

TEST(RingFlicker, ZeroForAStillSequenceAndTheAmplitudeForAnAlternatingOne) {
  const auto a = gradient(60, 40);
  const auto map = eccentricity_map(pinhole(60, 40, 50.0), {30, 20});
  for (double f : ring_flicker({a, a, a}, map)) EXPECT_EQ(f, 0.0);
  auto b = a;
  for (float& v : b.rgb) v += 0.1f;
  const auto f = ring_flicker({a, b, a, b}, map);
  for (std::size_t r = 0; r < kRingCount; ++r) {
    if (map.ring_pixels[r] > 0) {
      EXPECT_NEAR(f[r], 0.1, 1e-6) << r;
    }
  }
  for (double v : ring_flicker({a}, map)) EXPECT_EQ(v, 0.0);
}

TEST(ImageMetrics, SizeMismatchIsAnErrorNamingTheSizes) {
  const auto map = eccentricity_map(pinhole(20, 10, 20.0), {10, 5});
  try {
    compare_images(gradient(20, 10), gradient(20, 12), map);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("20x12"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace foveart::metrics
