// Per-canvas-pixel tables and the k-tap gather: same weights as the
// one-query code, deterministic, valid indices, constants, ties, range, fp16.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "foveation/gather.hpp"
#include "foveation/interpolation_table.hpp"
#include "interpolation_fixture.hpp"
#include "interpolation_test_util.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

using test::opts;

PointColors uniform_colors(std::size_t n, float r, float g, float b) {
  std::vector<float> rgb;
  for (std::size_t i = 0; i < n; ++i) rgb.insert(rgb.end(), {r, g, b});
  return point_colors_from_all(rgb);
}

PointColors random_colors(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> rgb(n * 3);
  for (float& v : rgb) v = u(rng);
  return point_colors_from_all(rgb);
}

class InterpolationTableTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    points_ = new PointSet(test::foveated_points());
    neighbors_ = new NeighborTable(NeighborTable::build(*points_, 20, test::executor()));
  }
  static void TearDownTestSuite() {
    delete points_;
    delete neighbors_;
  }
  static PointSet* points_;
  static NeighborTable* neighbors_;
};
PointSet* InterpolationTableTest::points_ = nullptr;
NeighborTable* InterpolationTableTest::neighbors_ = nullptr;

TEST_F(InterpolationTableTest, AllIndicesValid) {
  for (std::size_t p = 0; p < neighbors_->pixel_count(); ++p) {
    for (int j = 0; j < neighbors_->k(); ++j) ASSERT_LT(neighbors_->neighbor(p, j), points_->size());
  }
}

TEST_F(InterpolationTableTest, WeightsEqualTheOneQueryCode) {
  for (auto m : test::kAllMethods) {
    for (int k : {5, 20}) {
      const auto t = build_interpolation_table(*points_, *neighbors_, opts(m, k), test::executor(), WeightPrecision::f32);
      for (std::size_t p = 0; p < t.pixel_count(); p += 37) {
        std::vector<Vec2d> nb;
        std::vector<std::uint32_t> ids;
        for (int j = 0; j < k; ++j) {
          ids.push_back(neighbors_->neighbor(p, j));
          nb.push_back({points_->position_px[ids.back()].x, points_->position_px[ids.back()].y});
        }
        auto w = std::vector<double>(std::size_t(k));
        const Vec2d q{double(p % std::size_t(t.width_px)) + 0.5, double(p / std::size_t(t.width_px)) + 0.5};
        interpolation_weights(opts(m, k), nb, ids, q, w);
        for (int j = 0; j < t.taps(); ++j) ASSERT_EQ(t.weight(p, j), float(w[std::size_t(j)])) << method_name(m);
      }
    }
  }
}

TEST_F(InterpolationTableTest, IdenticalAcrossRunsAndThreadCounts) {
  Executor one_thread(1), three_threads(3);
  for (auto m : {InterpMethod::msm, InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    const auto a = build_interpolation_table(*points_, *neighbors_, opts(m, 10), one_thread, WeightPrecision::f32);
    const auto b = build_interpolation_table(*points_, *neighbors_, opts(m, 10), test::executor(), WeightPrecision::f32);
    const auto c = build_interpolation_table(*points_, *neighbors_, opts(m, 10), three_threads, WeightPrecision::f32);
    EXPECT_EQ(a.weights_f32, b.weights_f32) << method_name(m);
    EXPECT_EQ(a.weights_f32, c.weights_f32) << method_name(m);
    EXPECT_EQ(a.stats.fallback_msm, b.stats.fallback_msm);
  }
}

TEST_F(InterpolationTableTest, MsmWeightsNonNegativeAndNormalisedInFloat) {
  const auto t = build_interpolation_table(*points_, *neighbors_, opts(InterpMethod::msm, 20), test::executor(), WeightPrecision::f32);
  for (std::size_t p = 0; p < t.pixel_count(); ++p) {
    float sum = 0;
    for (int j = 0; j < 20; ++j) {
      ASSERT_GE(t.weight(p, j), 0.0f);
      sum += t.weight(p, j);
    }
    ASSERT_NEAR(sum, 1.0f, 1e-5f);
  }
}

TEST_F(InterpolationTableTest, GatherReproducesConstantsForEveryMethod) {
  const auto colors = uniform_colors(points_->size(), 0.25f, 0.5f, 0.75f);
  ImageRgb out;
  for (auto m : test::kAllMethods) {
    for (int k : {5, 20}) {
      {
        const auto prec = k == 20 ? WeightPrecision::f16 : WeightPrecision::f32;
        const auto t = build_interpolation_table(*points_, *neighbors_, opts(m, k), test::executor(), prec);
        gather(*neighbors_, t, colors, test::centre_mapping(), out, test::executor());
        for (std::size_t i = 0; i < out.pixel_count(); ++i) {
          ASSERT_NEAR(out.rgb[i * 3 + 0], 0.25f, 1e-6f) << method_name(m) << " k=" << k;
          ASSERT_NEAR(out.rgb[i * 3 + 2], 0.75f, 1e-6f) << method_name(m) << " k=" << k;
        }
      }
    }
  }
}

TEST_F(InterpolationTableTest, ThesisPlainRbfDarkensConstants) {
  const auto colors = uniform_colors(points_->size(), 1.0f, 1.0f, 1.0f);
  ImageRgb out;
  auto o = opts(InterpMethod::rbf, 5);
  o.constant_term = false;
  const auto t = build_interpolation_table(*points_, *neighbors_, o, test::executor(), WeightPrecision::f32);
  GatherOptions g;
  g.rbf_clamp = RbfClamp::off;
  gather(*neighbors_, t, colors, test::centre_mapping(), out, test::executor(), g);
  double worst = 0;
  for (float v : out.rgb) worst = std::max(worst, std::abs(double(v) - 1.0));
  EXPECT_GT(worst, 1e-3);
}

TEST_F(InterpolationTableTest, MsmGatherStaysWithinTapRange) {
  const auto colors = random_colors(points_->size(), 3);
  const auto t = build_interpolation_table(*points_, *neighbors_, opts(InterpMethod::msm, 10), test::executor(), WeightPrecision::f16);
  const auto map = test::centre_mapping();
  ImageRgb out;
  gather(*neighbors_, t, colors, map, out, test::executor());
  for (int y = 0; y < out.height_px; ++y) {
    for (int x = 0; x < out.width_px; ++x) {
      const std::size_t cp = std::size_t(y + map.canvas_from_screen_y_px) * std::size_t(t.width_px) +
                             std::size_t(x + map.canvas_from_screen_x_px);
      float lo = 1, hi = 0;
      for (int j = 0; j < 10; ++j) {
        lo = std::min(lo, colors.rgba[neighbors_->neighbor(cp, j)].r);
        hi = std::max(hi, colors.rgba[neighbors_->neighbor(cp, j)].r);
      }
      ASSERT_GE(out.at(x, y)[0], lo - 1e-6f);
      ASSERT_LE(out.at(x, y)[0], hi + 1e-6f);
    }
  }
}

TEST_F(InterpolationTableTest, RbfClampRemovesOvershootOnAStep) {
  std::vector<float> rgb;
  for (const auto& p : points_->position_px) {
    const float v = p.x < float(test::kScreenW) ? 0.0f : 1.0f;
    rgb.insert(rgb.end(), {v, v, v});
  }
  const auto colors = point_colors_from_all(rgb);
  const auto t = build_interpolation_table(*points_, *neighbors_, opts(InterpMethod::rbf, 20), test::executor(), WeightPrecision::f32);
  ImageRgb clamped, raw;
  gather(*neighbors_, t, colors, test::centre_mapping(), clamped, test::executor());
  GatherOptions g;
  g.rbf_clamp = RbfClamp::off;
  gather(*neighbors_, t, colors, test::centre_mapping(), raw, test::executor(), g);
  float lo = 0, hi = 1, rlo = 0, rhi = 1;
  for (float v : clamped.rgb) lo = std::min(lo, v), hi = std::max(hi, v);
  for (float v : raw.rgb) rlo = std::min(rlo, v), rhi = std::max(rhi, v);
  EXPECT_EQ(lo, 0.0f);
  EXPECT_EQ(hi, 1.0f);
  EXPECT_GT(std::max(-rlo, rhi - 1.0f), 0.01f);  // the weights alone do overshoot
  EXPECT_LT(std::max(-rlo, rhi - 1.0f), 0.75f);
}

TEST_F(InterpolationTableTest, HalfWeightsCostLittleAccuracy) {
  // Smooth colour field: compare half-weight and float-weight gathers.
  std::vector<float> rgb;
  for (const auto& p : points_->position_px) {
    rgb.insert(rgb.end(), {0.5f + 0.5f * std::sin(p.x * 0.2f), 0.5f + 0.5f * std::cos(p.y * 0.15f), 0.3f});
  }
  const auto colors = point_colors_from_all(rgb);
  for (auto m : {InterpMethod::msm, InterpMethod::rbf}) {
    const auto t32 = build_interpolation_table(*points_, *neighbors_, opts(m, 20), test::executor(), WeightPrecision::f32);
    const auto t16 = build_interpolation_table(*points_, *neighbors_, opts(m, 20), test::executor(), WeightPrecision::f16);
    EXPECT_EQ(t16.weights_f16.size(), t32.weights_f32.size());
    EXPECT_EQ(t16.bytes() + t16.weights_f16.size() * 2, t32.bytes());  // same layout, half the weight bytes
    EXPECT_LT(t16.stats.max_quantization_error, 0.01);
    ImageRgb a, b;
    gather(*neighbors_, t32, colors, test::centre_mapping(), a, test::executor());
    gather(*neighbors_, t16, colors, test::centre_mapping(), b, test::executor());
    double worst = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) worst = std::max(worst, std::abs(double(a.rgb[i]) - double(b.rgb[i])));
    EXPECT_LT(worst, 4e-3) << method_name(m);
    RecordProperty(std::string(method_name(m)) + "_f16_max_error", std::to_string(worst));
  }
}

TEST(InterpolationTableLattice, NearestNeighbourTiesGoToLowestIndex) {
  const auto points = test::lattice_points();
  const auto nt = NeighborTable::build(points, 4, test::executor());
  std::vector<float> rgb;
  for (std::size_t i = 0; i < points.size(); ++i) rgb.insert(rgb.end(), {float(i), 0.0f, 0.0f});
  const auto colors = point_colors_from_all(rgb);
  const auto t = build_interpolation_table(points, nt, opts(InterpMethod::nearest, 1), test::executor(), std::nullopt);
  const auto map = test::centre_mapping();
  ImageRgb out;
  gather(nt, t, colors, map, out, test::executor());
  for (int y = 0; y < out.height_px; ++y) {
    for (int x = 0; x < out.width_px; ++x) {
      const float cx = float(x + map.canvas_from_screen_x_px) + 0.5f, cy = float(y + map.canvas_from_screen_y_px) + 0.5f;
      std::uint32_t lowest = UINT32_MAX;
      for (std::size_t i = 0; i < points.size(); ++i) {
        if (std::abs(points.position_px[i].x - cx) == 0.5f && std::abs(points.position_px[i].y - cy) == 0.5f) {
          lowest = std::min(lowest, std::uint32_t(i));
        }
      }
      ASSERT_EQ(out.at(x, y)[0], float(lowest));
    }
  }
  // MSM on the same lattice: every pixel is the equidistant case, the mean of 4.
  const auto msm = build_interpolation_table(points, nt, opts(InterpMethod::msm, 4), test::executor(), WeightPrecision::f32);
  EXPECT_EQ(msm.stats.equidistant, msm.pixel_count());
}

}  // namespace
}  // namespace foveart::foveation
