// Content density on the device trace (gpu/device_trace.hpp, shaders/device_rays.comp,
// device_resolve.comp, device_density.glsl) on lavapipe, under
// VK_LAYER_KHRONOS_validation with synchronization validation (the fixture's
// TearDown): after a first frame, the points the device traces and the rays
// each casts are those the CPU's rule (foveation::ContentDensity, PointRays::
// rays_of) gives for the tiles of the colours the device resolved; flat content
// gives up points and rays while the pixel-exact fovea keeps every point and
// ray (the grid margin of a denser scale its points only), high contrast keeps
// them all; a fault makes the next frame trace every point; the frame
// reconstructs as the CPU path's content-density frame; and the device's stage
// set passes the view's content density to the device.
#include <algorithm>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "device_trace_harness.hpp"
#include "foveation/content_density.hpp"
#include "foveation/point_rays.hpp"
#include "foveation/visible_points.hpp"
#include "gpu/device_stages.hpp"
#include "threaded/small_view.hpp"

namespace foveart::gpu {
namespace {

using namespace device_test;  // NOLINT(google-build-using-namespace): the harness is this file's

constexpr uint32_t kDensityRays = 4;  // rays per point: room for the contrast to take some

// What the CPU's rule gives a frame: rays per point (0: not traced), thinned points, all rays.
struct DensityCounts {
  std::vector<uint32_t> rays;
  uint32_t thinned = 0;
  uint64_t total = 0;
};

class DeviceDensityTest : public DeviceTraceFixture {
 protected:
  void SetUp() override {
    DeviceTraceFixture::SetUp();
    settings_.rays_per_point = int(kDensityRays);
    settings_.content_density.full_contrast = 0.08f;
    settings_.content_density.rays_contrast = 0.16f;
  }
  void TearDown() override {
    for (BoundBuffer* b : {&engine_.rays, &engine_.point_index, &engine_.control, &engine_.footprints})
      destroy_buffer(engine_.device, b);
    DeviceTraceFixture::TearDown();
  }

  // A frame of `view` traced on the device with the view's content density, into
  // slot frame_index % kFrameSlots of `eye` (null: eye_).
  bool density_frame(foveation::FoveatedView& view, const foveation::FrameRequest& req, std::string* error,
                     Eye* eye = nullptr) {
    if (eye == nullptr) eye = eye_.get();
    foveation::Executor executor(2);
    if (!view.plan(req, executor).ok()) return *error = "the plan failed", false;
    const DeviceTraceFrame device = device_of(view, req);
    EyeFrame frame = EyeFrame::of(*gpu_tables_, view.hand_off(), true);
    frame.device = &device;
    frame.slot = uint32_t(req.frame_index % kFrameSlots);
    return gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) { return eye->record(cb, frame, VK_NULL_HANDLE, executor, error); }, error);
  }

  // Rays per point of the last frame, from the point indices the engine copied; the
  // rays of a point are consecutive.
  std::vector<uint32_t> copied_rays() const {
    std::vector<uint32_t> rays(tables_->points.size(), 0);
    const auto* control = static_cast<const uint32_t*>(engine_.control.mapped);
    const auto* index = static_cast<const uint32_t*>(engine_.point_index.mapped);
    for (uint32_t r = 0; r < control[0]; ++r) {
      EXPECT_TRUE(r == 0 || index[r] >= index[r - 1]) << "ray " << r << " out of the point set's order";
      ++rays.at(index[r]);
    }
    return rays;
  }

  // The CPU's rule for the frame at `now` after a frame at `before` whose points
  // `observed` (rays > 0) had the colours `rgba` (the device's, read back).
  DensityCounts cpu_rule(const foveation::GazeMapping& before, const std::vector<uint32_t>& observed,
                         const std::vector<float>& rgba, const foveation::GazeMapping& now) const {
    const foveation::PointSet& points = tables_->points;
    foveation::Executor executor(1);
    const foveation::PointLevels& levels = tables_->levels(executor);
    foveation::ContentDensity density(levels, settings_.content_density);
    density.begin_frame(before, 1);
    const foveation::VisibleRegion was(before, points.visible_margin_px);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (observed[i] == 0) continue;
      const foveation::Rgba c{rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], rgba[4 * i + 3]};
      density.observe(0, was.to_screen(points.position_px[i]), c);
    }
    density.end_frame(true);
    density.begin_frame(now, 1);
    const foveation::VisibleRegion is(now, points.visible_margin_px);
    const foveation::PointRays point_rays(points, int(kDensityRays), settings_.pixel_filter, true);
    const foveation::RaysContrastSteps rays_contrast =
        foveation::rays_contrast_steps(settings_.content_density.rays_contrast,
                                       settings_.content_density.rays_doubling_ecc_deg, points.view_distance_px);
    DensityCounts out;
    out.rays.assign(points.size(), 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const glm::vec2 screen = is.to_screen(points.position_px[i]);
      if (!is.contains(screen)) continue;
      const uint32_t parent = levels.parent[i][0];
      if (!density.traces(uint32_t(i), screen) && parent != foveation::PointLevels::kNoParent &&
          is.contains(is.to_screen(points.position_px[parent]))) {
        ++out.thinned;
        continue;
      }
      out.rays[i] = point_rays.rays_of(uint32_t(i), density.contrast(screen), rays_contrast);
      out.total += out.rays[i];
    }
    return out;
  }

  // Frame `index` at `gaze` on the device, compared point by point with the CPU's rule
  // from the last frame (mapping `before`, rays `observed`); returns this frame's rays.
  std::vector<uint32_t> expect_cpu_rule(foveation::FoveatedView& view, glm::vec2 gaze, uint64_t index,
                                        foveation::GazeMapping* before, const std::vector<uint32_t>& observed,
                                        DensityCounts* expected) {
    std::vector<float> rgba;
    std::string error;
    EXPECT_TRUE(eye_->read_point_colors(uint32_t((index - 1) % kFrameSlots), &rgba, &error)) << error;
    EXPECT_TRUE(density_frame(view, request(gaze, index), &error)) << error;
    *expected = cpu_rule(*before, observed, rgba, view.hand_off().mapping);
    *before = view.hand_off().mapping;
    const std::vector<uint32_t> rays = copied_rays();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) differ += rays[i] != expected->rays[i] ? 1 : 0;
    EXPECT_EQ(differ, 0u) << "points whose rays differ from the CPU's rule, frame " << index;
    const DeviceTraceStatus status = eye_->device_trace_status();
    EXPECT_EQ(status.rays, expected->total);
    EXPECT_EQ(status.thinned_points, expected->thinned);
    EXPECT_EQ(status.traced_points + status.thinned_points, status.visible_points);
    return rays;
  }
};

// After a first frame (every visible point, rays by its disc), each frame's points
// and rays per point are the CPU rule's for the tiles of the last frame's resolved
// colours (the direction engine: a smooth field whose tiles span the levels), over
// a gaze move; some points are thinned, some cast fewer rays, some all.
TEST_F(DeviceDensityTest, PointsAndRaysFollowTheCpuRule) {
  engine_.answer = TestEngine::Answer::direction;
  engine_.copy = true;
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  ASSERT_TRUE(density_frame(view, request(glm::vec2(48, 40), 0), &error)) << error;
  const DeviceTraceStatus first = eye_->device_trace_status();
  EXPECT_EQ(first.thinned_points, 0u);
  EXPECT_EQ(first.traced_points, first.visible_points);
  foveation::GazeMapping before = view.hand_off().mapping;
  std::vector<uint32_t> rays = copied_rays();
  DensityCounts expected;
  for (uint64_t i = 1; i < 4; ++i) {
    const glm::vec2 gaze = i < 3 ? glm::vec2(48, 40) : glm::vec2(56, 46);
    rays = expect_cpu_rule(view, gaze, i, &before, rays, &expected);
    std::size_t fewer = 0, all = 0;
    for (std::size_t p = 0; p < rays.size(); ++p) {
      fewer += rays[p] > 0 && rays[p] < kDensityRays ? 1 : 0;
      all += rays[p] == kDensityRays ? 1 : 0;
    }
    EXPECT_GT(expected.thinned, 0u) << "frame " << i;
    EXPECT_GT(fewer, 0u) << "frame " << i;
    EXPECT_GT(all, 0u) << "frame " << i;
    const uint64_t unthinned = uint64_t(first.visible_points) * kDensityRays;
    StageTimes times;
    ASSERT_TRUE(eye_->stage_times(&times));
    EXPECT_GT(times.density_fill_ms, 0.0f) << "frame " << i << ": the fill pass is timed";
    EXPECT_GT(times.density_contrast_ms, 0.0f) << "frame " << i << ": the contrast pass is timed";
    std::cout << "[ device density ] frame " << i << ": " << eye_->device_trace_status().rays << " rays of "
              << unthinned << " without content density, " << expected.thinned << " of "
              << eye_->device_trace_status().visible_points << " visible points thinned; GPU ms: trace "
              << times.trace_ms << ", of it fill " << times.density_fill_ms << ", contrast "
              << times.density_contrast_ms << "\n";
  }
}

// With the contrast doubling every 8 degrees of eccentricity (four steps, the last inside this
// 60-degree view's corners), each point's rays are still the CPU rule's, whose steps the device counts with the same
// float tests: the outer points cast fewer rays than without the steps.
TEST_F(DeviceDensityTest, RaysByEccentricityStepsFollowTheCpuRule) {
  engine_.answer = TestEngine::Answer::direction;
  engine_.copy = true;
  settings_.content_density.rays_doubling_ecc_deg = 8.0f;
  const foveation::RaysContrastSteps steps =
      foveation::rays_contrast_steps(settings_.content_density.rays_contrast, 8.0f, tables_->points.view_distance_px);
  ASSERT_LT(steps.distance_sq_px2[3], float(kViewW * kViewW + kViewH * kViewH) / 4.0f)
      << "the view's corners lie beyond every step";
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  ASSERT_TRUE(density_frame(view, request(glm::vec2(48, 40), 0), &error)) << error;
  foveation::GazeMapping before = view.hand_off().mapping;
  DensityCounts stepped;
  const std::vector<uint32_t> first_rays = copied_rays();
  const foveation::GazeMapping first_mapping = before;
  std::vector<float> rgba;
  ASSERT_TRUE(eye_->read_point_colors(0, &rgba, &error)) << error;
  expect_cpu_rule(view, glm::vec2(48, 40), 1, &before, first_rays, &stepped);
  settings_.content_density.rays_doubling_ecc_deg = 0.0f;  // the same tiles without the steps
  const DensityCounts flat_contrast = cpu_rule(first_mapping, first_rays, rgba, before);
  EXPECT_LT(stepped.total, flat_contrast.total) << "the steps take rays from the outer points";
  std::size_t fewer = 0;
  for (std::size_t p = 0; p < stepped.rays.size(); ++p) {
    EXPECT_LE(stepped.rays[p], flat_contrast.rays[p]) << "point " << p << ": a step never adds rays";
    fewer += stepped.rays[p] < flat_contrast.rays[p] ? 1 : 0;
  }
  EXPECT_GT(fewer, 0u);
  std::cout << "[ device density ] rays with the contrast doubling every 8 degrees: " << stepped.total << " of "
            << flat_contrast.total << " without\n";
}

// Flat content (every ray the same grey) gives up points and rays: the next frame's
// Poisson points are thinned or cast one ray, while the pixel-exact fovea keeps every
// point and every ray. Stripes (high contrast in every tile) then keep them all: the
// frame after a striped one traces as the first frame does.
TEST_F(DeviceDensityTest, FlatContentGivesUpRaysTheFoveaAndEdgesKeepThem) {
  engine_.answer = TestEngine::Answer::fill;
  engine_.copy = true;
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  const glm::vec2 gaze(48, 40);
  ASSERT_TRUE(density_frame(view, request(gaze, 0), &error)) << error;
  const DeviceTraceStatus first = eye_->device_trace_status();
  const std::vector<uint32_t> first_rays = copied_rays();
  ASSERT_TRUE(density_frame(view, request(gaze, 1), &error)) << error;
  const DeviceTraceStatus flat = eye_->device_trace_status();
  const std::vector<uint32_t> flat_rays = copied_rays();
  EXPECT_GT(flat.thinned_points, first.visible_points / 4);
  EXPECT_LT(flat.rays, first.rays);
  std::size_t grid = 0;
  for (std::size_t p = 0; p < flat_rays.size(); ++p) {
    if (first_rays[p] == 0) continue;  // not visible
    if (tables_->points.on_pixel_grid(p)) {
      ++grid;
      EXPECT_EQ(flat_rays[p], kDensityRays) << "fovea point " << p;
    } else {
      EXPECT_LE(flat_rays[p], 1u) << "flat point " << p;
    }
  }
  EXPECT_GT(grid, 0u);
  engine_.answer = TestEngine::Answer::stripes;
  ASSERT_TRUE(density_frame(view, request(gaze, 2), &error)) << error;
  ASSERT_TRUE(density_frame(view, request(gaze, 3), &error)) << error;
  EXPECT_EQ(eye_->device_trace_status().thinned_points, 0u);
  EXPECT_EQ(eye_->device_trace_status().rays, first.rays);
  EXPECT_EQ(copied_rays(), first_rays);
}

// At a scale below 1 the grid margin beyond the pixel-exact fovea keeps every point but
// casts by content as the CPU's rule does: flat content leaves it one ray a point, while the
// exact fovea keeps all.
TEST_F(DeviceDensityTest, TheGridMarginOfADenserScaleCastsByContentAsOnTheCpu) {
  std::string error;
  tables_ = foveation::small_view::grid_margin_tables(kViewW, kViewH, foveation::InterpMethod::msm, 5);
  gpu_tables_ = gpu_->upload_tables(tables_, &error);
  ASSERT_NE(gpu_tables_, nullptr) << error;
  engine_.answer = TestEngine::Answer::fill;
  engine_.copy = true;
  foveation::FoveatedView view(tables_, settings_);
  const glm::vec2 gaze(48, 40);
  ASSERT_TRUE(density_frame(view, request(gaze, 0), &error)) << error;
  foveation::GazeMapping before = view.hand_off().mapping;
  DensityCounts expected;
  const std::vector<uint32_t> flat_rays = expect_cpu_rule(view, gaze, 1, &before, copied_rays(), &expected);
  const foveation::PointSet& points = tables_->points;
  std::size_t exact = 0, margin = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (!points.on_pixel_grid(p) || expected.rays[p] == 0) continue;  // not visible, or a Poisson point
    if (points.in_exact_fovea(p)) {
      ++exact;
      EXPECT_EQ(flat_rays[p], kDensityRays) << "fovea point " << p;
    } else {
      ++margin;
      EXPECT_EQ(flat_rays[p], 1u) << "margin point " << p;
    }
  }
  EXPECT_GT(exact, 2000u);
  EXPECT_GT(margin, 1000u);
}

// A frame whose colours are NaN (found by the resolve) leaves no contrast: the next
// frame traces every visible point as the first frame does; the one after thins again.
TEST_F(DeviceDensityTest, AFaultMakesTheNextFrameTraceEveryPoint) {
  engine_.answer = TestEngine::Answer::fill;
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  const glm::vec2 gaze(48, 40);
  ASSERT_TRUE(density_frame(view, request(gaze, 0), &error)) << error;
  const DeviceTraceStatus first = eye_->device_trace_status();
  engine_.fill_bits = 0x7FC00000u;  // NaN
  ASSERT_TRUE(density_frame(view, request(gaze, 1), &error)) << error;
  EXPECT_GT(eye_->device_trace_status().invalid_components, 0u);
  engine_.fill_bits = bits_of(kConstant);
  ASSERT_TRUE(density_frame(view, request(gaze, 2), &error)) << error;
  EXPECT_EQ(eye_->device_trace_status().thinned_points, 0u);
  EXPECT_EQ(eye_->device_trace_status().rays, first.rays);
  ASSERT_TRUE(density_frame(view, request(gaze, 3), &error)) << error;
  EXPECT_GT(eye_->device_trace_status().thinned_points, 0u);
}

// The device's content-density frame reconstructs as the CPU path's (FoveatedView's
// CallbackTrace with the same options, its colours uploaded) within one 8-bit step,
// both engines answering each ray with its direction, over a gaze jump. Each path has
// its own eye: an eye's frame that does not measure the tiles leaves the next unthinned.
TEST_F(DeviceDensityTest, FrameMatchesTheCpuContentDensityFrame) {
  engine_.answer = TestEngine::Answer::direction;
  foveation::FoveatedView device_view(tables_, settings_), callback_view(tables_, settings_);
  std::string error;
  const auto device_eye = gpu_->create_eye(kViewW, kViewH, &error);
  ASSERT_NE(device_eye, nullptr) << error;
  for (uint64_t i = 0; i < 4; ++i) {
    const foveation::FrameRequest req = request(i < 2 ? glm::vec2(40, 30) : glm::vec2(70, 60), i);
    ASSERT_TRUE(callback_frame(callback_view, req, &direction_colour, nullptr, &error)) << error;
    std::vector<uint8_t> expected, actual;
    ASSERT_TRUE(eye_->read_rgba8(&expected, &error)) << error;
    ASSERT_TRUE(density_frame(device_view, req, &error, device_eye.get())) << error;
    ASSERT_TRUE(device_eye->read_rgba8(&actual, &error)) << error;
    ASSERT_EQ(actual.size(), expected.size());
    int worst = 0;
    for (std::size_t b = 0; b < actual.size(); ++b)
      worst = std::max(worst, std::abs(int(actual[b]) - int(expected[b])));
    EXPECT_LE(worst, 1) << "frame " << i;
    EXPECT_EQ(device_eye->device_trace_status().thinned_points > 0, i > 0) << "frame " << i;
  }
}

// The device's stage set (make_device_stages) takes the view's content density:
// its frames are those recorded from the planned hand-off with the same options, bit
// for bit, and its second frame thins.
TEST_F(DeviceDensityTest, DeviceStageSetTakesTheViewsContentDensity) {
  engine_.answer = TestEngine::Answer::direction;
  foveation::FoveatedView planned(tables_, settings_);
  foveation::FoveatedView staged(tables_, settings_,
                                 make_device_stages(tables_, settings_, [this](const DeviceRayBatch& batch) {
                                   return test_engine(&engine_, &batch);
                                 }));
  std::string error;
  const auto staged_eye = gpu_->create_eye(kViewW, kViewH, &error);
  ASSERT_NE(staged_eye, nullptr) << error;
  foveation::Executor executor(2);
  for (uint64_t i = 0; i < 3; ++i) {
    const foveation::FrameRequest req = request(glm::vec2(48, 40), i);
    ASSERT_TRUE(density_frame(planned, req, &error)) << error;
    DeviceFrame frame;
    frame.eye = staged_eye.get();
    frame.tables = gpu_tables_.get();
    frame.slot = uint32_t(req.frame_index % kFrameSlots);
    foveation::FrameResult result;
    ASSERT_TRUE(gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) {
          frame.cb = cb;
          result = staged.render(req, nullptr, nullptr, frame, executor);
          return result.ok();
        },
        &error))
        << result.message << error;
    std::vector<uint8_t> expected, actual;
    ASSERT_TRUE(eye_->read_rgba8(&expected, &error)) << error;
    ASSERT_TRUE(staged_eye->read_rgba8(&actual, &error)) << error;
    EXPECT_EQ(actual, expected) << "frame " << i;
    EXPECT_EQ(staged_eye->device_trace_status().rays, eye_->device_trace_status().rays) << "frame " << i;
    EXPECT_EQ(staged_eye->device_trace_status().thinned_points > 0, i > 0) << "frame " << i;
  }
}

// With content density the resolve runs a thread per traced point and the fill one
// per thinned point, each sized on the device: after a flat frame many points are
// thinned, the resolve's groups are those of the traced points (fewer than those of
// the visible), the fill's those of the thinned, and every visible point, traced or
// filled, and no other, has a colour.
TEST_F(DeviceDensityTest, ResolveAndFillRunOverTheTracedAndThinnedPointsOnly) {
  const uint32_t group = FOVEART_DEVICE_RESOLVE_GROUP;
  const auto groups = [group](std::size_t n) { return uint32_t((n + group - 1) / group); };
  engine_.answer = TestEngine::Answer::fill;
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  ASSERT_TRUE(density_frame(view, request(glm::vec2(48, 40), 0), &error)) << error;
  ASSERT_TRUE(density_frame(view, request(glm::vec2(48, 40), 1), &error)) << error;
  const DeviceTraceStatus status = eye_->device_trace_status();
  const std::vector<uint32_t> control = last_control_words();
  ASSERT_GT(status.thinned_points, 0u);
  EXPECT_EQ(control[FOVEART_DEVICE_TRACED_POINTS], status.traced_points);
  EXPECT_EQ(control[FOVEART_DEVICE_THINNED_POINTS], status.thinned_points);
  EXPECT_EQ(control[FOVEART_DEVICE_RESOLVE_DISPATCH], groups(status.traced_points));
  EXPECT_EQ(control[FOVEART_DEVICE_FILL_DISPATCH], groups(status.thinned_points));
  EXPECT_EQ(control[FOVEART_DEVICE_FILL_DISPATCH + 1], 1u);
  EXPECT_EQ(control[FOVEART_DEVICE_FILL_DISPATCH + 2], 1u);
  EXPECT_LT(control[FOVEART_DEVICE_RESOLVE_DISPATCH], groups(status.visible_points));
  const std::vector<bool> visible = visible_at(view.hand_off().mapping);
  EXPECT_EQ(uint32_t(std::count(visible.begin(), visible.end(), true)), status.visible_points);
  EXPECT_EQ(coloured_unlike(1, visible), 0u);
}

}  // namespace
}  // namespace foveart::gpu
