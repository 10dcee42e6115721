// The sample-history controls: every ray since the last restart, anchored where
// it hit and traced again each frame (or its colour kept, a render cache),
// filtered into pixels with the pixel filter (eval/sample_history.hpp).
#include <eval/sample_history.hpp>

#include "analytic_scene.hpp"

#include <foveation/eye_rays.hpp>

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include <atomic>
#include <cmath>

namespace foveart {
namespace {

using foveation::ImageRgb;
using foveation::PixelFilter;

constexpr std::uint32_t kW = 48, kH = 40;

struct Engine {
  foveation::test::AnalyticScene scene;
  int calls = 0;
  int fail_from_call = -1;  // >= 0: that call and every later one fails
  std::atomic<std::size_t> rays{0};  // traced, over every call (the executor's threads call at once)
};

std::int32_t trace(void* user, const FoveartRayBatch* batch) {
  auto* e = static_cast<Engine*>(user);
  if (e->fail_from_call >= 0 && e->calls++ >= e->fail_from_call) return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  e->rays += batch->ray_count;
  for (std::uint32_t i = 0; i < batch->ray_count; ++i) {
    const float* o = batch->origins_m + 3 * i;
    const float* d = batch->directions + 3 * i;
    float depth = 0.0f;
    const glm::vec3 c = e->scene.shade({o[0], o[1], o[2]}, {d[0], d[1], d[2]}, &depth);
    for (int k = 0; k < 3; ++k) batch->out_rgb[3 * i + k] = c[k];
    if (batch->size >= FOVEART_RAY_BATCH_SIZE_WITH_DEPTH) batch->out_depth_m[i] = depth;
  }
  return FOVEART_RESULT_SUCCESS;
}

FoveartEyeView view_at(glm::vec3 position_m, float yaw_deg) {
  foveation::EyePose pose;
  pose.position_m = position_m;
  pose.orientation = glm::angleAxis(glm::radians(-yaw_deg), glm::vec3(0, 1, 0));
  return foveation::make_eye_view(0, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
}

// On a still view every ray stays: frame n holds n rays per pixel, and each
// pixel is the mean of its own (box) over every frame so far.
TEST(SampleHistory, StillViewAveragesEveryRaySinceTheRestart) {
  Engine engine;
  engine.scene.near_bar = false;
  foveation::Executor executor(2);
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 0.0f);
  const foveation::EyeFrustum f = foveation::eye_frustum(view);
  const foveation::EyePose pose = foveation::eye_pose(view);
  constexpr std::uint64_t kSeed = 7;
  constexpr int kFrames = 4;
  eval::SampleHistory history(kSeed, PixelFilter::box);
  ImageRgb out;
  for (int frame = 0; frame < kFrames; ++frame) {
    ASSERT_EQ(history.render(&trace, &engine, view, std::uint64_t(frame), frame == 0, executor, &out),
              FOVEART_RESULT_SUCCESS);
    EXPECT_EQ(history.rays(), std::size_t(frame + 1) * kW * kH);
  }
  // The expectation, ray by ray: the same jitter (seed + frame), traced from the eye.
  int off_by_more = 0;
  double abs_sum = 0.0;
  for (std::uint32_t y = 0; y < kH; ++y)
    for (std::uint32_t x = 0; x < kW; ++x) {
      const std::uint64_t p = std::uint64_t(y) * kW + x;
      glm::vec3 sum(0.0f);
      for (int frame = 0; frame < kFrames; ++frame) {
        const glm::vec2 q = glm::vec2(float(x), float(y)) + foveation::pixel_jitter(p, 0, kSeed + std::uint64_t(frame));
        float depth = 0.0f;
        sum += engine.scene.shade(pose.position_m, foveation::eye_ray_direction(f, pose, q), &depth);
      }
      for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(double(out.at(int(x), int(y))[c]) - double(sum[c]) / kFrames);
        abs_sum += d;
        off_by_more += d > 1e-4 ? 1 : 0;
      }
    }
  // A ray re-projected through its hit point lands where it was to float
  // rounding; one on a pixel's very edge may change pixel: a handful at most.
  EXPECT_LE(off_by_more, 6);
  EXPECT_LT(abs_sum / (3.0 * kW * kH), 1e-4);
}

TEST(SampleHistory, RestartForgetsEveryRayAndRepeatsAFreshHistory) {
  Engine engine;
  foveation::Executor executor(2);
  eval::SampleHistory history(3, PixelFilter::bspline2), fresh(3, PixelFilter::bspline2);
  ImageRgb out, fresh_out;
  for (int frame = 0; frame < 3; ++frame)
    ASSERT_EQ(history.render(&trace, &engine, view_at({0, 1.6f, 0}, 0.5f * float(frame)), std::uint64_t(frame),
                             frame == 0, executor, &out),
              FOVEART_RESULT_SUCCESS);
  EXPECT_GT(history.rays(), 2u * kW * kH);
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 2.0f);
  ASSERT_EQ(history.render(&trace, &engine, view, 3, true, executor, &out), FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(history.rays(), std::size_t(kW) * kH);
  ASSERT_EQ(fresh.render(&trace, &engine, view, 3, true, executor, &fresh_out), FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(out.rgb, fresh_out.rgb);
}

// Kept rays follow the surface they hit: an eye stepping sideways in front of
// a wall 10 m away carries its oldest rays off the image's edge (and forgets
// them), while rays that hit nothing keep their direction and stay.
TEST(SampleHistory, KeptRaysAreAnchoredWhereTheyHit) {
  foveation::Executor executor(2);
  for (const bool at_infinity : {false, true}) {
    Engine engine;
    engine.scene.near_bar = false;
    engine.scene.wall_at_infinity = at_infinity;
    eval::SampleHistory history(5, PixelFilter::box);
    ImageRgb out;
    constexpr int kFrames = 5;
    for (int frame = 0; frame < kFrames; ++frame)  // 0.2 m a frame: 0.96 px at 10 m
      ASSERT_EQ(history.render(&trace, &engine, view_at({0.2f * float(frame), 1.6f, 0}, 0.0f),
                               std::uint64_t(frame), frame == 0, executor, &out),
                FOVEART_RESULT_SUCCESS);
    if (at_infinity) {
      EXPECT_EQ(history.rays(), std::size_t(kFrames) * kW * kH);
    } else {
      // Frame k's rays moved 0.96 (4 - k) px: 9.6 columns of rays left the image in all.
      EXPECT_LT(history.rays(), std::size_t(kFrames) * kW * kH - 8u * kH);
      EXPECT_GT(history.rays(), std::size_t(kFrames) * kW * kH - 11u * kH);
    }
  }
}

// Under a turning head the output stays an estimate of the filtered image:
// closer to the supersampled truth than one ray per pixel is.
TEST(SampleHistory, TurningHeadConvergesTowardsTheTruth) {
  Engine engine;
  foveation::Executor executor(2);
  eval::SampleHistory history(11, PixelFilter::box);
  ImageRgb out;
  FoveartEyeView view{};
  constexpr int kFrames = 12;
  for (int frame = 0; frame < kFrames; ++frame) {
    view = view_at({0.01f * float(frame), 1.6f, 0}, 0.3f * float(frame));
    ASSERT_EQ(history.render(&trace, &engine, view, std::uint64_t(frame), frame == 0, executor, &out),
              FOVEART_RESULT_SUCCESS);
  }
  const ImageRgb truth = engine.scene.render(view, 8);
  eval::SampleHistory one(11, PixelFilter::box);
  ImageRgb one_ray;
  ASSERT_EQ(one.render(&trace, &engine, view, kFrames - 1, true, executor, &one_ray), FOVEART_RESULT_SUCCESS);
  const auto rms = [&](const ImageRgb& a) {
    double sq = 0.0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) sq += std::pow(double(a.rgb[i]) - double(truth.rgb[i]), 2.0);
    return std::sqrt(sq / double(a.rgb.size()));
  };
  EXPECT_LT(rms(out), 0.5 * rms(one_ray)) << rms(out) << " against " << rms(one_ray);
}

TEST(SampleHistory, EngineFailureIsReturnedAndKeepsTheRaysItHad) {
  Engine engine;
  foveation::Executor executor(2);
  eval::SampleHistory history(2, PixelFilter::box);
  ImageRgb out;
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 0.0f);
  ASSERT_EQ(history.render(&trace, &engine, view, 0, true, executor, &out), FOVEART_RESULT_SUCCESS);
  engine.fail_from_call = 0;
  EXPECT_EQ(history.render(&trace, &engine, view, 1, false, executor, &out), FOVEART_RESULT_ERROR_ENGINE_FAILURE);
  EXPECT_EQ(history.rays(), std::size_t(kW) * kH);
}

// A render cache on a still view is the history without error, tracing only
// the frame's new rays: every kept ray's colour is what tracing it again gives.
// The near bar's edges cross pixels: each edge pixel's new ray lands on the
// bar in some frames and on the wall in others, and the wall's kept rays there
// are still seen, so the depth test must keep them.
TEST(RayCache, StillViewTracesOnlyTheNewRaysAndMatchesTheRetracedHistory) {
  foveation::Executor executor(2);
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 0.0f);
  constexpr int kFrames = 4;
  for (const PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2}) {
    Engine retraced_engine, cached_engine;
    eval::SampleHistory retraced(9, filter, eval::RayReuse::retrace);
    eval::SampleHistory cached(9, filter, eval::RayReuse::keep_colour);
    ImageRgb retraced_out, cached_out;
    for (int frame = 0; frame < kFrames; ++frame) {
      ASSERT_EQ(
          retraced.render(&trace, &retraced_engine, view, std::uint64_t(frame), frame == 0, executor, &retraced_out),
          FOVEART_RESULT_SUCCESS);
      ASSERT_EQ(cached.render(&trace, &cached_engine, view, std::uint64_t(frame), frame == 0, executor, &cached_out),
                FOVEART_RESULT_SUCCESS);
    }
    const char* name = foveation::pixel_filter_name(filter);
    EXPECT_EQ(cached_engine.rays.load(), std::size_t(kFrames) * kW * kH) << name << ": one new ray per pixel a frame";
    EXPECT_EQ(retraced_engine.rays.load(), std::size_t(kFrames) * (kFrames + 1) / 2 * kW * kH) << name;
    EXPECT_EQ(cached.rays(), retraced.rays()) << name << ": no kept ray is dropped on a still view";
    // A ray traced again through its own hit point lands on it to float rounding.
    double max_diff = 0.0;
    for (std::size_t i = 0; i < cached_out.rgb.size(); ++i)
      max_diff = std::max(max_diff, std::fabs(double(cached_out.rgb[i]) - double(retraced_out.rgb[i])));
    EXPECT_LT(max_diff, 1e-3) << name;
  }
}

// The render cache's depth test: an eye stepping sideways carries the near bar
// (1 m) across the far wall (10 m); the wall's kept rays that the bar now
// covers must be forgotten, so the bar's pixels show the bar alone.
TEST(RayCache, RaysANearerSurfaceCoversAreForgotten) {
  foveation::Executor executor(2);
  for (const PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2}) {
    SCOPED_TRACE(foveation::pixel_filter_name(filter));
    Engine engine;
    eval::SampleHistory cached(4, filter, eval::RayReuse::keep_colour);
    ImageRgb out;
    FoveartEyeView view{};
    constexpr int kFrames = 6;
    for (int frame = 0; frame < kFrames; ++frame) {  // 4 cm a frame: the bar moves ~2 px, the wall ~0.2 px
      view = view_at({0.04f * float(frame), 1.6f, 0}, 0.0f);
      ASSERT_EQ(cached.render(&trace, &engine, view, std::uint64_t(frame), frame == 0, executor, &out),
                FOVEART_RESULT_SUCCESS);
    }
    std::vector<float> depth_m;
    engine.scene.render(view, 1, &depth_m);
    const auto bar_at = [&](int x, int y) { return depth_m[std::size_t(y) * kW + std::size_t(x)] < 2.0f; };
    // The bar's pixels away from its edges by more than a ray's reach (bspline2 spreads it 1.5 px)
    // and the jitter around a pixel (1.5 px more).
    const int margin = filter == PixelFilter::box ? 1 : 3;
    int inside_bar = 0, mixed = 0;
    for (int y = margin; y + margin < int(kH); ++y)
      for (int x = margin; x + margin < int(kW); ++x) {
        bool interior = true;
        for (int dy = -margin; dy <= margin; ++dy)
          for (int dx = -margin; dx <= margin; ++dx) interior = interior && bar_at(x + dx, y + dy);
        if (!interior) continue;
        ++inside_bar;
        const float* px = out.at(x, y);
        if (std::fabs(px[0] - 0.9f) > 1e-3f || std::fabs(px[1] - 0.1f) > 1e-3f) ++mixed;
      }
    EXPECT_GT(inside_bar, 20) << "the premise: the bar covers pixels";
    EXPECT_EQ(mixed, 0) << "of " << inside_bar << " pixels inside the bar, some still hold the wall's kept rays";
    EXPECT_LT(cached.rays(), std::size_t(kFrames) * kW * kH) << "the covered rays are gone for good";
  }
}

}  // namespace
}  // namespace foveart
