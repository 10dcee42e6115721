// Invalid point colours (NaN/Inf from an engine, points not sampled this frame)
// never spread into the image: the rule of gather.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "foveation/gather.hpp"
#include "foveation/interpolation_table.hpp"
#include "interpolation_fixture.hpp"
#include "interpolation_test_util.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

using test::opts;

struct Setup {
  PointSet points = test::foveated_points(5);
  NeighborTable nt = NeighborTable::build(points, 20, test::executor());
  GazeMapping map = test::centre_mapping();
};

const Setup& setup() {
  static const Setup s;
  return s;
}

std::size_t canvas_pixel(const Setup& s, int x, int y) {
  return std::size_t(y + s.map.canvas_from_screen_y_px) * std::size_t(s.nt.width_px()) +
         std::size_t(x + s.map.canvas_from_screen_x_px);
}

TEST(InterpolationInvalid, PointColoursMarkNaNInfAndUnlisted) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<float> rgb = {0.1f, 0.2f, 0.3f, nan, 0, 0, 0, inf, 0, 1, 1, 1};
  const auto all = point_colors_from_all(rgb);
  EXPECT_EQ(all.invalid, 2u);
  EXPECT_EQ(all.rgba[1].a, 0.0f);
  EXPECT_EQ(all.rgba[1].r, 0.0f);  // the NaN is not kept
  const std::vector<std::uint8_t> valid = {1, 1, 1, 0};
  EXPECT_EQ(point_colors_from_all(rgb, valid).invalid, 3u);
  const std::vector<std::uint32_t> listed = {4, 0};
  const auto some = point_colors_from_list(6, listed, std::vector<float>{1, 1, 1, nan, 0, 0});
  EXPECT_EQ(some.invalid, 5u);
  EXPECT_EQ(some.rgba[4].a, 1.0f);
  EXPECT_THROW(point_colors_from_list(3, listed, std::vector<float>{1, 1, 1, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(point_colors_from_all(std::vector<float>{1, 2}), std::invalid_argument);
}

TEST(InterpolationInvalid, NaNPointNeverSpreads) {
  const auto& s = setup();
  std::vector<float> rgb(s.points.size() * 3, 0.5f);
  // Poison the nearest point of the screen centre and a handful of others.
  const std::uint32_t poisoned = s.nt.neighbor(canvas_pixel(s, test::kScreenW / 2, test::kScreenH / 2), 0);
  for (std::uint32_t i = poisoned; i < s.points.size(); i += 97) {
    rgb[i * 3] = std::numeric_limits<float>::quiet_NaN();
    rgb[i * 3 + 1] = std::numeric_limits<float>::infinity();
    rgb[i * 3 + 2] = -std::numeric_limits<float>::infinity();
  }
  const auto colors = point_colors_from_all(rgb);
  for (auto m : test::kAllMethods) {
    for (int k : {5, 20}) {
      if (m == InterpMethod::nearest && k == 20) continue;  // NN has one tap whatever k is
      const auto t = build_interpolation_table(s.points, s.nt, opts(m, k), test::executor(), WeightPrecision::f16);
      ImageRgb out;
      const auto stats = gather(s.nt, t, colors, s.map, out, test::executor());
      for (float v : out.rgb) ASSERT_NEAR(v, 0.5f, 1e-6f) << method_name(m) << " k=" << k;  // valid points are all 0.5
      EXPECT_GT(stats.renormalized + stats.nearest_valid, 0u);
      EXPECT_EQ(stats.fallback, 0u);
    }
  }
}

TEST(InterpolationInvalid, UnsampledPointsUseNearestValidOrFallback) {
  const auto& s = setup();
  // Only points left of the canvas centre were sampled.
  std::vector<std::uint32_t> listed;
  std::vector<float> rgb;
  for (std::uint32_t i = 0; i < s.points.size(); ++i) {
    if (s.points.position_px[i].x < float(test::kScreenW)) {
      listed.push_back(i);
      rgb.insert(rgb.end(), {0.2f, 0.4f, 0.6f});
    }
  }
  const auto colors = point_colors_from_list(s.points.size(), listed, rgb);
  GatherOptions g;
  g.fallback_rgb = {-1.0f, -1.0f, -1.0f};
  for (auto m : test::kAllMethods) {
    const auto t = build_interpolation_table(s.points, s.nt, opts(m, 10), test::executor(), WeightPrecision::f32);
    ImageRgb out;
    const auto stats = gather(s.nt, t, colors, s.map, out, test::executor(), g);
    EXPECT_GT(stats.fallback, 0u);  // right edge: no sampled point within 20 neighbours
    for (int y = 0; y < out.height_px; ++y) {
      for (int x = 0; x < out.width_px; ++x) {
        const float v = out.at(x, y)[0];
        const std::size_t cp = canvas_pixel(s, x, y);
        bool any_valid = false;
        for (int j = 0; j < s.nt.k(); ++j) any_valid |= colors.rgba[s.nt.neighbor(cp, j)].a != 0.0f;
        ASSERT_NEAR(v, any_valid ? 0.2f : -1.0f, 1e-6f) << method_name(m) << " at " << x << "," << y;
      }
    }
  }
}

TEST(InterpolationInvalid, AllInvalidGivesTheFallbackColour) {
  const auto& s = setup();
  const auto colors = point_colors_from_list(s.points.size(), {}, {});
  GatherOptions g;
  g.fallback_rgb = {0.0f, 1.0f, 0.0f};
  const auto t = build_interpolation_table(s.points, s.nt, opts(InterpMethod::rbf, 5), test::executor(), std::nullopt);
  ImageRgb out;
  const auto stats = gather(s.nt, t, colors, s.map, out, test::executor(), g);
  EXPECT_EQ(stats.fallback, out.pixel_count());
  for (std::size_t i = 0; i < out.pixel_count(); ++i) ASSERT_EQ(out.rgb[i * 3 + 1], 1.0f);
}

TEST(InterpolationInvalid, GatherRejectsMismatchedInputs) {
  const auto& s = setup();
  const auto colors = point_colors_from_list(s.points.size(), {}, {});
  const auto t = build_interpolation_table(s.points, s.nt, opts(InterpMethod::msm, 5), test::executor(), std::nullopt);
  ImageRgb out;
  GazeMapping bad = s.map;
  bad.canvas_from_screen_x_px = s.nt.width_px();  // screen leaves the canvas
  EXPECT_THROW(gather(s.nt, t, colors, bad, out, test::executor()), std::invalid_argument);
  EXPECT_THROW(gather(s.nt, t, PointColors{}, s.map, out, test::executor()), std::invalid_argument);
  EXPECT_THROW(build_interpolation_table(s.points, s.nt, opts(InterpMethod::msm, 21), test::executor()), std::invalid_argument);
}

}  // namespace
}  // namespace foveart::foveation
