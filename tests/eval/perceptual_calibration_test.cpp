// The image path of the perceptual metric against its own CSF path: a Gabor drawn at
// castleCSF's threshold contrast for it must give P = 0.5 (d = 1), across frequency,
// luminance, eccentricity and where the frequency falls between the pyramid's bands.
#include <gtest/gtest.h>

#include <cstdio>
#include <iostream>

#include "eval/castle_csf.hpp"
#include "foveation/srgb.hpp"
#include "perceptual_stimulus.hpp"
#include "under_sanitizer.hpp"

namespace {

using namespace foveart::test;
using foveart::eval::PerceptualMetric;

// log10 of the metric's response at castleCSF's threshold contrast: 0 when the image path
// agrees with the CSF, > 0 when it is more sensitive.
double identity_error(const GaborStimulus& s) {
  const GaborScene scene(s);
  PerceptualMetric m;
  std::string error;
  EXPECT_TRUE(PerceptualMetric::create(scene.display(), scene.width, scene.height, {}, m, error)) << error;
  const double c = 1.0 / foveart::eval::castle_sensitivity(
                             {s.freq_cpd, s.luminance_cd_m2, M_PI * s.sigma_deg * s.sigma_deg, s.ecc_deg, s.vis_field_deg});
  const double c_t = metric_threshold_contrast(scene, m, c);
  return std::log10(c / c_t);
}

}  // namespace

// The identity over 0.5-16 cpd x 1-100 cd/m^2 x 0-30 deg (both fields), Gabors of 1.5 cycles per
// sigma, each frequency at 8-64 pixels per degree so that it falls at different places between
// the pyramid's octave bands. Stimuli castleCSF puts above contrast 0.5 (at 30 deg, 8 and 16 cpd)
// cannot be drawn at threshold and are skipped. Bounds: RMS 0.05 log10 over the grid, and no
// single stimulus beyond 3 x that (an outlier check). What remains is the image path's
// discretisation: the half-octave bands' least-squares ripple between their centres (a few
// hundredths), the pyramid's residual aliasing at 1/4 and 1/8 cycle per pixel, the Gabor's own
// bandwidth and the spread of the bands' pooling areas around A_c(f) for a Gabor smaller than it.
TEST(PerceptualMetricCalibration, GaborAtCastleThresholdGivesHalfProbability) {
  const double ppds[] = {8.0, 16.0, 32.0, 64.0};
  const int stride = kUnderSanitizer ? 4 : 1;  // under the sanitizers every 4th stimulus (each is still checked)
  double sum2 = 0.0, worst = 0.0;
  int n = 0, skipped = 0, index = 0;
  std::printf("| f cpd | L cd/m2 | ecc deg | field | ppd | log10 d at castleCSF threshold |\n");
  for (double f : {0.5, 1.0, 2.0, 4.0, 8.0, 16.0})
    for (double lum : {1.0, 10.0, 100.0})
      for (double ecc : {0.0, 10.0, 30.0}) {
        GaborStimulus s;
        s.freq_cpd = f;
        s.sigma_deg = 1.5 / f;
        s.luminance_cd_m2 = lum;
        s.ecc_deg = ecc;
        s.vis_field_deg = index % 2 == 0 ? 180.0 : 0.0;
        s.pixels_per_deg = ppds[index++ % 4];
        while (f > s.pixels_per_deg / 2.5) s.pixels_per_deg *= 2.0;
        const double c = 1.0 / foveart::eval::castle_sensitivity(
                                   {f, lum, M_PI * s.sigma_deg * s.sigma_deg, ecc, s.vis_field_deg});
        if (c > 0.5 || (index - 1) % stride != 0) {
          ++skipped;
          continue;
        }
        const double err = identity_error(s);
        std::printf("| %g | %g | %g | %s | %g | %+.3f |\n", f, lum, ecc, s.vis_field_deg == 0.0 ? "temporal" : "nasal",
                    s.pixels_per_deg, err);
        sum2 += err * err;
        worst = std::max(worst, std::abs(err));
        ++n;
        EXPECT_LE(std::abs(err), 0.15) << f << " cpd, " << lum << " cd/m^2, " << ecc << " deg";
      }
  const double rms = std::sqrt(sum2 / n);
  std::printf("%d stimuli (%d skipped): RMS %.3f, largest %.3f log10\n", n, skipped, rms, worst);
  if (kUnderSanitizer) return;
  EXPECT_GE(n, 36);  // most of the grid is drawable
  EXPECT_LE(rms, 0.05);
}

// The metric's luminance is linear in the display-linear values: images that hold sRGB-encoded
// display values (the price list's, a PNG's) must be decoded first (PerceptualInput::kSrgbEncoded).
// A Gabor at the metric's threshold, drawn in display-linear values, then sRGB-encoded, gives
// P = 0.5 again when decoded; read as if linear (what the price list once did) it reads as
// about a quarter of its contrast on a brighter background, far below threshold.
TEST(PerceptualMetricCalibration, SrgbEncodedImagesAreDecodedBeforeLuminance) {
  GaborStimulus s;
  s.freq_cpd = 4.0;
  s.sigma_deg = 1.5 / s.freq_cpd;
  s.luminance_cd_m2 = 10.0;
  const GaborScene scene(s);
  PerceptualMetric linear_metric, encoded_metric;
  std::string error;
  ASSERT_TRUE(PerceptualMetric::create(scene.display(), scene.width, scene.height, {}, linear_metric, error)) << error;
  foveart::eval::PerceptualDisplay encoded_display = scene.display();
  encoded_display.input = foveart::eval::PerceptualInput::kSrgbEncoded;
  ASSERT_TRUE(PerceptualMetric::create(encoded_display, scene.width, scene.height, {}, encoded_metric, error)) << error;
  const double c_t = metric_threshold_contrast(scene, linear_metric, 0.01);
  const auto encode = [](foveart::foveation::ImageRgb img) {
    for (float& v : img.rgb) v = foveart::foveation::linear_to_srgb(v);
    return img;
  };
  const foveart::foveation::ImageRgb test = encode(scene.image(c_t)), ref = encode(scene.image(0.0));
  const glm::vec2 gaze{float(scene.gaze_x), float(scene.gaze_y)};
  foveart::eval::PerceptualResult decoded, as_linear;
  ASSERT_TRUE(encoded_metric.evaluate(test, ref, gaze, nullptr, decoded, error)) << error;
  ASSERT_TRUE(linear_metric.evaluate(test, ref, gaze, nullptr, as_linear, error)) << error;
  std::printf("threshold contrast %.4f: P %.3f decoded, %.3f read as linear\n", c_t, decoded.p_max, as_linear.p_max);
  EXPECT_NEAR(decoded.p_max, 0.5, 0.01);
  EXPECT_LT(as_linear.p_max, 0.1);
}
