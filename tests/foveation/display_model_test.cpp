// Thesis eqs. 1-4 against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "foveation/display_model.hpp"

namespace fv = foveart::foveation;

TEST(DisplayModel, Eq1EccentricityIsDegreesOfAtan) {
  // d = N v: 45 degrees; d = 0: 0; radians converted to degrees.
  EXPECT_NEAR(fv::eccentricity_deg(1000.0, 1000.0), 45.0, 1e-12);
  EXPECT_EQ(fv::eccentricity_deg(0.0, 1000.0), 0.0);
  EXPECT_NEAR(fv::eccentricity_deg(100.0, 1000.0), 5.710593137499643, 1e-12);
  EXPECT_NEAR(fv::eccentricity_deg(100.0, 1000.0, 2.0), 2.0 * 5.710593137499643, 1e-12);
}

TEST(DisplayModel, Eq2CutoffFrequency) {
  // e2 ln(64) / ((e + e2) alpha) = 2.3 * 4.1588830833596715 / (2.3 * 0.106) at e = 0.
  EXPECT_NEAR(fv::cutoff_frequency_cpd(0.0), 39.23474607, 1e-6);
  EXPECT_NEAR(fv::cutoff_frequency_cpd(10.0), 2.3 * 4.1588830833596715 / (12.3 * 0.106), 1e-9);
  EXPECT_GT(fv::cutoff_frequency_cpd(1.0), fv::cutoff_frequency_cpd(2.0));
}

TEST(DisplayModel, Eq3DisplayNyquist) {
  EXPECT_NEAR(fv::display_nyquist_cpd(360.0), 3.141592653589793, 1e-12);
  EXPECT_NEAR(fv::display_nyquist_cpd(1088.0), 9.494591, 1e-6);
}

TEST(DisplayModel, Eq4SpacingIsCappedNearTheFovea) {
  const double a = std::sqrt(1.0 / 3.141592653589793);
  EXPECT_NEAR(fv::kPixelDiscRadiusPx, a, 1e-15);
  // f_c > f_d near the fovea: f_c0 = f_d, p = 1 - (1 - a) = a.
  EXPECT_NEAR(fv::point_radius_px(9.49, 39.2), a, 1e-12);
  // Beyond the cap: p = f_d / f_c - (1 - a).
  EXPECT_NEAR(fv::point_radius_px(9.49, 2.0), 9.49 / 2.0 - (1.0 - a), 1e-12);
  // A whole model: radius is a inside the cap, then grows monotonically.
  const auto d = fv::DisplayModel::from_thesis(1280, 1440, 0.85);
  EXPECT_NEAR(d.radius_px(0.0), a, 1e-12);
  EXPECT_NEAR(d.radius_px(20.0), a, 1e-12);  // ~1 degree: still capped
  double last = 0.0;
  for (double dist = 0.0; dist < 2000.0; dist += 7.0) {
    const double r = d.radius_px(dist);
    EXPECT_GE(r, last - 1e-12);
    last = r;
  }
  // The cap ends where f_c(e) = f_d: e = e2 ln(1/CT0) / (alpha f_d) - e2.
  const double e_cap = 2.3 * std::log(64.0) / (0.106 * d.display_cpd()) - 2.3;
  const double d_cap = d.view_distance_px * std::tan(e_cap * 3.141592653589793 / 180.0);
  EXPECT_NEAR(d.radius_px(d_cap * 0.99), a, 1e-12);
  EXPECT_GT(d.radius_px(d_cap * 1.05), a + 1e-3);
}

TEST(DisplayModel, ScaleMultipliesEccentricity) {
  auto d = fv::DisplayModel::from_thesis(1280, 1440, 0.85);
  const double e1 = d.ecc_deg(500.0);
  d.scale = 2.0;
  EXPECT_NEAR(d.ecc_deg(500.0), 2.0 * e1, 1e-12);
  EXPECT_GT(d.radius_px(500.0), fv::DisplayModel::from_thesis(1280, 1440, 0.85).radius_px(500.0));
}

TEST(DisplayModel, ThreeWaysToGiveADisplayAgree) {
  const auto by_fov = fv::DisplayModel::from_fov(1280, 1440, 90.0);
  EXPECT_NEAR(by_fov.view_distance_px, 640.0, 1e-9);  // tan 45 = 1
  EXPECT_NEAR(by_fov.horizontal_fov_deg(), 90.0, 1e-9);
  const auto by_ppd = fv::DisplayModel::from_pixels_per_degree(1280, 1440, 640.0 * 3.141592653589793 / 180.0);
  EXPECT_NEAR(by_ppd.view_distance_px, 640.0, 1e-9);
  const auto by_thesis = fv::DisplayModel::from_thesis(1280, 1440, 0.5);
  EXPECT_NEAR(by_thesis.view_distance_px, 640.0, 1e-9);
}

TEST(DisplayModel, PresetsAndValidation) {
  for (const auto& name : fv::display_preset_names()) {
    const auto d = fv::display_preset(name);
    ASSERT_TRUE(d.has_value()) << name;
    EXPECT_EQ(d->validate(), "") << name;
  }
  EXPECT_FALSE(fv::display_preset("oculus").has_value());
  const auto fove = *fv::display_preset("fove");
  EXPECT_EQ(fove.width_px, 1280);
  EXPECT_EQ(fove.height_px, 1440);
  EXPECT_NEAR(fove.horizontal_fov_deg(), 95.0, 1e-9);

  EXPECT_NE(fv::DisplayModel::from_fov(0, 1440, 90).validate(), "");
  EXPECT_NE(fv::DisplayModel::from_fov(1280, -1, 90).validate(), "");
  EXPECT_NE(fv::DisplayModel::from_fov(1280, 1440, 180).validate(), "");
  EXPECT_NE(fv::DisplayModel::from_fov(1280, 1440, 0).validate(), "");
  EXPECT_NE(fv::DisplayModel::from_pixels_per_degree(1280, 1440, 0).validate(), "");
  auto bad_scale = fove;
  bad_scale.scale = 0.0;
  EXPECT_NE(bad_scale.validate(), "");
  bad_scale.scale = std::nan("");
  EXPECT_NE(bad_scale.validate(), "");
}
