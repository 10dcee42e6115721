// TAA history reprojection (foveation/history_reprojection.hpp) against analytic
// renders: a yaw (rotation only, no depth needed) and a sideways step of the
// eye in front of a near bar and a far wall (parallax: needs depth, and the
// bar's trailing edge uncovers wall the history never saw).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "analytic_scene.hpp"
#include "foveation/history_reprojection.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

constexpr uint32_t kW = 96, kH = 80;

FoveartEyeView view_at(glm::vec3 position_m, float yaw_deg) {
  EyePose pose;
  pose.position_m = position_m;
  pose.orientation = glm::angleAxis(glm::radians(-yaw_deg), glm::vec3(0, 1, 0));
  return make_eye_view(0, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
}

// The striped wall at infinity alone: a yaw needs no depth.
test::AnalyticScene sky_only() {
  test::AnalyticScene sky;
  sky.wall_at_infinity = true;
  sky.near_bar = false;
  return sky;
}

// RMS over the valid pixels (all when `valid` is empty) and the count.
double rms(const ImageRgb& a, const ImageRgb& b, const std::vector<std::uint8_t>& valid, std::size_t* n = nullptr) {
  double sq = 0.0;
  std::size_t count = 0;
  for (std::size_t p = 0; p < a.pixel_count(); ++p) {
    if (!valid.empty() && valid[p] == 0) continue;
    for (int c = 0; c < 3; ++c) sq += std::pow(double(a.rgb[p * 3 + c]) - double(b.rgb[p * 3 + c]), 2.0);
    ++count;
  }
  if (n != nullptr) *n = count;
  return count > 0 ? std::sqrt(sq / double(count * 3)) : 0.0;
}

TEST(TaaReprojection, YawNeedsNoDepth) {
  const test::AnalyticScene sky = sky_only();
  const auto before = view_at({0, 1.6f, 0}, 0.0f), after = view_at({0, 1.6f, 0}, 3.0f);
  const ImageRgb history = sky.render(before, 1), truth = sky.render(after, 1);
  ImageRgb warped;
  std::vector<std::uint8_t> valid;
  const auto stats = reproject_history(history, {}, before, after, {}, warped, valid, test::executor());
  std::size_t kept = 0;
  const double err = rms(warped, truth, valid, &kept);
  const double stale = rms(history, truth, {});  // the history where it was: what a restart-free TAA without reprojection blends
  // 3 deg of a 57 deg wide view leaves the view on one side: about 5% of the columns.
  EXPECT_GT(stats.off_screen, std::size_t(kH) * 2);
  EXPECT_LT(stats.off_screen, std::size_t(kH) * 10);
  EXPECT_EQ(kept + stats.off_screen, std::size_t(kW) * kH);
  EXPECT_EQ(stats.with_depth, 0u);
  std::printf("yaw 3 deg: RMS %.4f reprojected, %.4f stale; %llu px off-screen\n", err, stale,
              static_cast<unsigned long long>(stats.off_screen));
  EXPECT_LT(err, 0.06) << "stale history: " << stale;  // bilinear resampling of 40 cycles/rad stripes
  EXPECT_LT(err * 4.0, stale);
}

TEST(TaaReprojection, CatmullRomKeepsTheDetailBilinearBlursWithoutOvershoot) {
  const test::AnalyticScene sky = sky_only();
  const auto before = view_at({0, 1.6f, 0}, 0.0f), after = view_at({0, 1.6f, 0}, 1.3f);
  const ImageRgb history = sky.render(before, 1), truth = sky.render(after, 1);
  ImageRgb bilinear, catmull_rom;
  std::vector<std::uint8_t> valid_bilinear, valid_catmull_rom;
  reproject_history(history, {}, before, after, {}, bilinear, valid_bilinear, test::executor(),
                    HistorySampling::bilinear);
  reproject_history(history, {}, before, after, {}, catmull_rom, valid_catmull_rom, test::executor(),
                    HistorySampling::catmull_rom);
  EXPECT_EQ(valid_bilinear, valid_catmull_rom) << "the sampling does not change which history holds";
  const double err_bilinear = rms(bilinear, truth, valid_bilinear), err_catmull_rom = rms(catmull_rom, truth, valid_catmull_rom);
  std::printf("yaw 1.3 deg (a fractional shift): RMS %.4f bilinear, %.4f Catmull-Rom\n", err_bilinear, err_catmull_rom);
  EXPECT_LT(err_catmull_rom, 0.8 * err_bilinear);
  // Clamped to the 2x2 pixels around: never outside the history's own range.
  float lo = INFINITY, hi = -INFINITY;
  for (float v : history.rgb) lo = std::min(lo, v), hi = std::max(hi, v);
  for (std::size_t i = 0; i < catmull_rom.rgb.size(); ++i) {
    if (valid_catmull_rom[i / 3] == 0) continue;
    ASSERT_GE(catmull_rom.rgb[i], lo);
    ASSERT_LE(catmull_rom.rgb[i], hi);
  }
}

TEST(TaaReprojection, ParallaxFollowsDepthAndRejectsUncoveredWall) {
  test::AnalyticScene scene;
  const auto before = view_at({0, 1.6f, 0}, 0.0f), after = view_at({0.04f, 1.6f, 0}, 0.0f);
  std::vector<float> depth_before, depth_after;
  const ImageRgb history = scene.render(before, 1, &depth_before), truth = scene.render(after, 1, &depth_after);

  ImageRgb with_depth, rotation_only;
  std::vector<std::uint8_t> valid_depth, valid_rotation;
  const auto s = reproject_history(history, depth_before, before, after, depth_after, with_depth, valid_depth,
                                   test::executor());
  reproject_history(history, {}, before, after, {}, rotation_only, valid_rotation, test::executor());
  EXPECT_EQ(s.with_depth, std::size_t(kW) * kH);  // every pixel hits the bar or the wall
  EXPECT_GT(s.disoccluded, 0u) << "the bar moved 4 cm against the wall: wall it hid is uncovered";
  const double err_depth = rms(with_depth, truth, valid_depth);
  const double err_rotation = rms(rotation_only, truth, valid_rotation);
  std::printf("step 4 cm: RMS %.4f with depth, %.4f rotation only; %llu px disoccluded\n", err_depth, err_rotation,
              static_cast<unsigned long long>(s.disoccluded));
  EXPECT_LT(err_depth, 0.05);
  EXPECT_GT(err_rotation, 3.0 * err_depth) << "rotation-only history ghosts the near bar";
}

TEST(TaaReprojection, SameViewIsTheHistoryItself) {
  test::AnalyticScene scene;
  const auto view = view_at({0, 1.6f, 0}, 10.0f);
  std::vector<float> depth;
  const ImageRgb history = scene.render(view, 1, &depth);
  ImageRgb warped;
  std::vector<std::uint8_t> valid;
  const auto s = reproject_history(history, depth, view, view, depth, warped, valid, test::executor());
  EXPECT_EQ(s.off_screen, 0u);
  EXPECT_EQ(s.disoccluded, 0u);
  EXPECT_LT(rms(warped, history, {}), 1e-5);
}

}  // namespace
}  // namespace foveart::foveation
