// Gabor stimuli drawn as images for the perceptual metric's image path, placed at an
// eccentricity and visual field from the gaze on a display whose mean is the stimulus's
// background luminance, and the metric's threshold for them (perceptual_validation_test.cpp,
// perceptual_calibration_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "eval/perceptual_metric.hpp"

namespace foveart::test {

struct GaborStimulus {
  double freq_cpd = 4.0;
  double sigma_deg = 0.5;        // Gaussian envelope; castleCSF's area is pi sigma^2
  double luminance_cd_m2 = 100.0;
  double ecc_deg = 0.0;
  double vis_field_deg = 180.0;  // right eye: 0 temporal (+x), 90 up (-y), 180 nasal
  double pixels_per_deg = 20.0;  // at the gaze
};

// The image: the gaze, the stimulus at its eccentricity (flat-screen mapping, e = atan(d / D)),
// and 3 sigma (+ 8 px) around both. The carrier runs along the radial direction.
struct GaborScene {
  const GaborStimulus s;
  double view_distance_px = 0, ppd_radial = 0, ppd_tangential = 0;
  int width = 0, height = 0;
  double gaze_x = 0, gaze_y = 0, cx = 0, cy = 0, dir_x = 1, dir_y = 0;

  explicit GaborScene(const GaborStimulus& stim) : s(stim) {
    constexpr double kDegPerRad = 180.0 / M_PI;
    view_distance_px = s.pixels_per_deg * kDegPerRad;
    const double e = s.ecc_deg / kDegPerRad;
    ppd_radial = view_distance_px / (std::cos(e) * std::cos(e)) / kDegPerRad;
    ppd_tangential = view_distance_px / std::cos(e) / kDegPerRad;
    const double vf = s.vis_field_deg / kDegPerRad;
    dir_x = std::cos(vf);
    dir_y = -std::sin(vf);
    const double dist = view_distance_px * std::tan(e);
    const double half = 3.0 * s.sigma_deg * ppd_radial + 8.0;
    const double min_x = std::min(0.0, dir_x * dist) - half, max_x = std::max(0.0, dir_x * dist) + half;
    const double min_y = std::min(0.0, dir_y * dist) - half, max_y = std::max(0.0, dir_y * dist) + half;
    width = int(std::ceil(max_x - min_x));
    height = int(std::ceil(max_y - min_y));
    gaze_x = -min_x;
    gaze_y = -min_y;
    cx = gaze_x + dir_x * dist;
    cy = gaze_y + dir_y * dist;
  }

  foveation::ImageRgb image(double contrast) const {
    foveation::ImageRgb img(width, height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double px = x - cx, py = y - cy;
        const double u = (px * dir_x + py * dir_y) / ppd_radial;       // degrees, radial
        const double v = (-px * dir_y + py * dir_x) / ppd_tangential;  // degrees, tangential
        const double env = std::exp(-(u * u + v * v) / (2.0 * s.sigma_deg * s.sigma_deg));
        const float value = float(0.5 * (1.0 + contrast * env * std::cos(2.0 * M_PI * s.freq_cpd * u)));
        std::fill_n(img.at(x, y), 3, value);
      }
    return img;
  }

  // Display: black 0, white twice the background, so that value 0.5 is the background luminance.
  eval::PerceptualDisplay display() const {
    eval::PerceptualDisplay d;
    d.pixels_per_deg = s.pixels_per_deg;
    d.white_luminance_cd_m2 = 2.0 * s.luminance_cd_m2;
    d.black_luminance_cd_m2 = 0.0;
    return d;
  }
};

// The metric's largest detection probability over the image for the stimulus at `contrast`.
inline double metric_p_max(const GaborScene& scene, const eval::PerceptualMetric& m, double contrast) {
  eval::PerceptualResult out;
  std::string error;
  EXPECT_TRUE(m.evaluate(scene.image(contrast), scene.image(0.0), {float(scene.gaze_x), float(scene.gaze_y)},
                         nullptr, out, error))
      << error;
  return out.p_max;
}

// The pooled threshold-unit response d behind P = 1 - 0.5^(d^beta) (perceptual_metric.hpp).
inline double response_of_probability(double p) {
  return std::pow(std::log1p(-std::min(p, 1.0 - 1e-7)) / std::log(0.5), 1.0 / 3.5);
}

// The metric's threshold contrast (max P = 0.5). Against a uniform reference there is no masking
// and the response d is proportional to contrast, so c_t = c / d(c); two steps from a guess, and
// the result is checked: P at c_t must be 0.5 +- 0.005, so the shortcut cannot hide an error.
inline double metric_threshold_contrast(const GaborScene& scene, const eval::PerceptualMetric& m, double guess) {
  double c = std::clamp(guess, 1e-5, 1.0);
  for (int i = 0; i < 2; ++i) {
    const double d = response_of_probability(metric_p_max(scene, m, c));
    if (!(d > 0.0)) return 1.0;
    c = std::min(1.0, c / d);
  }
  const double p = metric_p_max(scene, m, c);
  EXPECT_TRUE(c >= 1.0 || std::abs(p - 0.5) < 0.005) << "P at the threshold found: " << p;
  return c;
}

}  // namespace foveart::test
