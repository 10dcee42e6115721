// The render cache ("temporal": "rays") fed by the device trace on lavapipe,
// under validation with synchronization validation: the device trace's rays
// go into the cache on the device, with each pixel's footprint and covering
// distance computed there (shaders/cache_device_rays.comp, cache_pixels.comp)
// and the kept count never read back on the frame path. Against the CPU's
// render cache of the same engine traced by the callback: the same rays kept
// every frame, frames equal within a tolerance per eccentricity ring, with
// content density too; a
// faulted view (NaN colours) restarts the cache on the device; and along the
// lab's scripted motion it flickers at least 5x less than no history beyond
// 20 deg, by the lab's measure (eval::TemporalError).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "device_trace_harness.hpp"
#include "eval/motion_sequence.hpp"
#include "eval/motion_views.hpp"
#include "eval/temporal_metrics.hpp"
#include "foveation/history_reprojection.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/srgb.hpp"
#include "metrics/image_metrics.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/rgba8.hpp"

namespace foveart::gpu {
namespace {

using namespace device_test;  // NOLINT(google-build-using-namespace): the harness is this file's

// The comparison's rings: the lab's (metrics::kRingEdgesDeg, eccentricity_map).
constexpr std::size_t kCacheRings = metrics::kRingCount;

struct RingDifference {
  std::array<int, kCacheRings> max_step{};
  std::array<double, kCacheRings> mean_step{};
};

// The largest and the mean difference in 8-bit steps per ring (RGB; alpha is 255 on both).
RingDifference ring_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                               const foveation::FrameRequest& req) {
  const std::vector<std::uint8_t> ring = metrics::eccentricity_map(req.view, req.gaze_px).ring;
  RingDifference d;
  std::array<std::size_t, kCacheRings> n{};
  for (std::size_t p = 0; p < ring.size(); ++p)
    for (std::size_t c = 0; c < 3; ++c) {
      const int step = std::abs(int(a[4 * p + c]) - int(b[4 * p + c]));
      d.max_step[ring[p]] = std::max(d.max_step[ring[p]], step);
      d.mean_step[ring[p]] += step;
      ++n[ring[p]];
    }
  for (std::size_t r = 0; r < kCacheRings; ++r) d.mean_step[r] /= double(std::max<std::size_t>(n[r], 1));
  return d;
}

// Frame i of the motion: the head turns 0.3 degrees a frame and steps 5 mm
// aside; at frame kSaccadeFrame a saccade moves the gaze (the cache restarts).
constexpr int kSaccadeFrame = 5;
foveation::FrameRequest moving_request(int i) {
  foveation::FrameRequest r = request(i < kSaccadeFrame ? glm::vec2(48, 40) : glm::vec2(30, 52), uint64_t(i + 1));
  foveation::EyePose pose = foveation::eye_pose(r.view);
  pose.orientation = glm::angleAxis(glm::radians(0.3f * float(i)), glm::vec3(0, 1, 0)) * pose.orientation;
  pose.position_m.x += 0.005f * float(i);
  r.view = foveation::make_eye_view(0, kViewW, kViewH, pose, -0.4f, 0.42f, 0.38f, -0.36f);
  r.saccade = i == kSaccadeFrame;
  return r;
}

int32_t nan_colour(void*, const FoveartRayBatch* batch) {
  std::fill_n(batch->out_rgb, std::size_t(batch->ray_count) * 3, std::numeric_limits<float>::quiet_NaN());
  return FOVEART_RESULT_SUCCESS;
}

class DeviceRayCacheTest : public DeviceTraceFixture {
 protected:
  void SetUp() override {
    DeviceTraceFixture::SetUp();
    settings_.temporal = foveation::TemporalMode::rays;
    settings_.pixel_filter = foveation::PixelFilter::bspline2;  // "rays"' filter (temporal_view_settings)
    engine_.answer = TestEngine::Answer::direction;
  }
  foveation::ViewSettings cpu_settings() const {
    foveation::ViewSettings s = settings_;
    s.reconstruct_on_cpu = true;
    return s;
  }
  // The CPU's frame of `view` (the callback's colours), encoded as the GPU encodes; *result its result.
  std::vector<uint8_t> cpu_frame(foveation::FoveatedView& view, const foveation::FrameRequest& req,
                                 FoveartTraceRaysFn trace, foveation::FrameResult* result) {
    foveation::Executor executor(2);
    *result = view.render(req, trace, nullptr, executor);
    std::vector<uint8_t> out(std::size_t(kViewW) * kViewH * 4);
    foveation::encode_rgba8(view.image(), true, foveation::DisplayTransform{}, out.data(), executor);
    return out;
  }
  // The eye's shown frame (read back after the submission) against `expected`, per ring of `req`.
  bool shown_difference(const std::vector<uint8_t>& expected, const foveation::FrameRequest& req, RingDifference* d,
                        std::string* error) {
    std::vector<uint8_t> actual;
    if (!eye_->read_rgba8(&actual, error)) return false;
    if (actual.size() != expected.size()) return *error = "the shown frame's size differs", false;
    *d = ring_difference(expected, actual, req);
    return true;
  }
};


// With a device trace, "rays" keeps exactly the CPU's rays every frame (the
// kept count, read back here only after each frame was waited for), over a
// moving head and a saccade, and gives the CPU's frames within a tolerance per
// ring, from how the two differ: the device trace's jitter is the CPU's
// (pixel-grid samples bit-exact, disc samples within 1e-3 px, directions and
// so the direction engine's colours within 1e-5: device_trace_test.cpp), the
// pixels' footprints and covering distances follow the same rule from the
// same hits, and the cache's sums run in the order the atomics gave (float
// rounding: reconstruction_test.cpp's cache test, one 8-bit step). A 1e-3 px
// shift moves a bspline2 weight (slope at most 1 per px) by at most 1e-3 of a
// ray's weight, so a value by at most a quarter step (1e-3 of 255): every ring's
// largest difference is one step, a value near a step's edge rounding the
// other way. Few values lie that near (typical disc samples agree far closer
// than the bound), so each ring's mean stays under a hundredth of a step; a
// wrong footprint, covering decision or kept ray moves whole regions and
// fails both. Measured on lavapipe: at most 1 step, means below 0.001.
TEST_F(DeviceRayCacheTest, DeviceTracedRaysCacheAsTheCpuCacheDoes) {
  foveation::FoveatedView cpu_view(tables_, cpu_settings()), device_view(tables_, settings_);
  RingDifference worst;
  for (int i = 0; i < 8; ++i) {
    const foveation::FrameRequest req = moving_request(i);
    foveation::FrameResult cpu;
    const std::vector<uint8_t> expected = cpu_frame(cpu_view, req, &direction_colour, &cpu);
    ASSERT_TRUE(cpu.ok());
    std::string error;
    ASSERT_TRUE(device_frame(device_view, req, &error)) << error;
    EXPECT_EQ(eye_->device_trace_status().invalid_components, 0u);
    EXPECT_EQ(device_view.hand_off().temporal.ray_restart, cpu_view.hand_off().temporal.ray_restart) << "frame " << i;
    EXPECT_EQ(eye_->cached_rays_after_wait(), cpu_view.cached_rays()) << "frame " << i;
    RingDifference d;
    ASSERT_TRUE(shown_difference(expected, req, &d, &error)) << error;
    for (std::size_t r = 0; r < kCacheRings; ++r) {
      worst.max_step[r] = std::max(worst.max_step[r], d.max_step[r]);
      worst.mean_step[r] = std::max(worst.mean_step[r], d.mean_step[r]);
    }
  }
  for (std::size_t r = 0; r < kCacheRings; ++r) {
    std::printf("ring %.1f-%.1f deg: max %d steps, mean %.4f steps\n", metrics::kRingEdgesDeg[r],
                metrics::kRingEdgesDeg[r + 1], worst.max_step[r], worst.mean_step[r]);
    EXPECT_LE(worst.max_step[r], 1) << "ring " << r;
    EXPECT_LT(worst.mean_step[r], 0.01) << "ring " << r;
  }
  EXPECT_GT(cpu_view.cached_rays(), 0u);
  EXPECT_EQ(engine_.calls, 8u);
}

// With content density beside the render cache, the device trace's cache takes only
// the traced points' rays, each point's as many as the contrast gave it, and a thinned
// point gives the pixels around it no covering distance: every frame, over the moving
// head and the saccade, it keeps exactly the CPU cache's rays, thins the CPU's points
// (both from the same rule on colours within float rounding: device_density_test.cpp)
// and gives the CPU's frame within the tolerance above.
TEST_F(DeviceRayCacheTest, WithContentDensityTheDeviceCacheKeepsTheCpuCachesRays) {
  settings_.rays_per_point = 4;  // room for the contrast to take some
  settings_.content_density.full_contrast = 0.08f;
  settings_.content_density.rays_contrast = 0.16f;
  foveation::FoveatedView cpu_view(tables_, cpu_settings()), device_view(tables_, settings_);
  foveation::FoveatedView unthinned(tables_, [&] {
    foveation::ViewSettings s = cpu_settings();
    s.content_density = {};
    return s;
  }());
  foveation::Executor executor(2);
  for (int i = 0; i < 8; ++i) {
    const foveation::FrameRequest req = moving_request(i);
    foveation::FrameResult cpu;
    const std::vector<uint8_t> expected = cpu_frame(cpu_view, req, &direction_colour, &cpu);
    ASSERT_TRUE(cpu.ok()) << cpu.message;
    const foveation::FrameResult all = unthinned.render(req, &direction_colour, nullptr, executor);
    ASSERT_TRUE(all.ok()) << all.message;
    std::string error;
    ASSERT_TRUE(device_frame(device_view, req, &error)) << error;
    const DeviceTraceStatus status = eye_->device_trace_status();
    EXPECT_EQ(status.invalid_components, 0u);
    EXPECT_EQ(status.thinned_points, cpu.points_thinned) << "frame " << i;
    EXPECT_EQ(status.rays, cpu.rays) << "frame " << i;
    if (i > 0) {
      EXPECT_GT(cpu.points_thinned, 0u) << "frame " << i;
      EXPECT_LT(cpu.rays, all.rays) << "frame " << i;
    }
    EXPECT_EQ(eye_->cached_rays_after_wait(), cpu_view.cached_rays()) << "frame " << i;
    RingDifference d;
    ASSERT_TRUE(shown_difference(expected, req, &d, &error)) << error;
    for (std::size_t r = 0; r < kCacheRings; ++r) {
      EXPECT_LE(d.max_step[r], 1) << "frame " << i << ", ring " << r;
      EXPECT_LT(d.mean_step[r], 0.01) << "frame " << i << ", ring " << r;
    }
  }
  std::printf("[ measured ] last frame: %zu rays kept, of them %llu new of %llu without content density\n",
              cpu_view.cached_rays(), static_cast<unsigned long long>(eye_->device_trace_status().rays),
              static_cast<unsigned long long>(unthinned.cached_rays()));
}

// A faulted view (the engine writes NaN) restarts the cache on the device:
// that frame's end keeps no ray, so the next frame holds none from before,
// though the host, which has not read the status yet, asked for no restart.
// The CPU's history restarts after its failed frame alike: the next frame
// keeps the CPU's rays again.
TEST_F(DeviceRayCacheTest, AFaultedViewRestartsTheCacheOnTheDevice) {
  foveation::FoveatedView cpu_view(tables_, cpu_settings()), device_view(tables_, settings_);
  std::string error;
  foveation::FrameResult cpu;
  for (int i = 0; i < 3; ++i) {
    cpu_frame(cpu_view, moving_request(i), &direction_colour, &cpu);
    ASSERT_TRUE(device_frame(device_view, moving_request(i), &error)) << error;
  }
  const std::size_t kept_before = eye_->cached_rays_after_wait();
  EXPECT_GT(kept_before, 0u);
  EXPECT_EQ(kept_before, cpu_view.cached_rays());

  engine_.answer = TestEngine::Answer::fill;
  engine_.fill_bits = 0x7FC00000u;  // NaN
  cpu_frame(cpu_view, moving_request(3), &nan_colour, &cpu);
  EXPECT_FALSE(cpu.ok()) << "the CPU's frame fails";
  ASSERT_TRUE(device_frame(device_view, moving_request(3), &error)) << error;
  EXPECT_GT(eye_->device_trace_status().invalid_components, 0u);
  EXPECT_EQ(eye_->cached_rays_after_wait(), 0u) << "the faulted frame keeps nothing";

  engine_.answer = TestEngine::Answer::direction;
  const foveation::FrameRequest next = moving_request(4);
  const std::vector<uint8_t> expected = cpu_frame(cpu_view, next, &direction_colour, &cpu);
  ASSERT_TRUE(cpu.ok());
  ASSERT_TRUE(device_frame(device_view, next, &error)) << error;
  EXPECT_FALSE(device_view.hand_off().temporal.ray_restart) << "the host did not ask for the restart";
  EXPECT_TRUE(cpu_view.hand_off().temporal.ray_restart);
  const std::size_t kept_after = eye_->cached_rays_after_wait();
  EXPECT_EQ(kept_after, cpu_view.cached_rays()) << "only the new frame's rays";
  EXPECT_LT(kept_after, kept_before);
  RingDifference d;
  ASSERT_TRUE(shown_difference(expected, next, &d, &error)) << error;
  for (std::size_t r = 0; r < kCacheRings; ++r) EXPECT_LE(d.max_step[r], 1) << "ring " << r;
}

// The scripted motion's frames (eval::motion_frames of the built-in motion:
// the head turning at 20 deg/s with tremor, the gaze fixating with
// microsaccades) from its start at 70 Hz, the eye at rest the harness's view.
// Its first 0.26 s turn the head 5 deg.
std::vector<eval::MotionFrame> scripted_frames(int frames) {
  std::string error;
  const auto motion = eval::load_motion("builtin", &error);
  EXPECT_TRUE(motion.has_value()) << error;
  if (!motion) return {};
  const eval::MotionWindow window{0.0, 70.0, frames};
  EXPECT_TRUE(eval::check_motion_window(*motion, window, &error)) << error;
  const FoveartEyeView at_rest = request(glm::vec2(48, 40), 1).view;
  return eval::motion_frames(*motion, window, at_rest, foveation::eye_pose(at_rest));
}

// stripes_engine.comp's colour of a direction: a sky of stripes.
glm::vec3 stripes_colour(glm::vec3 d) {
  const glm::vec3 phase(0.0f, 2.0f, 4.0f);
  return glm::vec3(0.5f) + 0.4f * glm::sin(60.0f * d + phase);
}

// The truth of the stripes engine's frame in display values: each pixel's
// bspline2-filtered colour (6 x 6 taps over the filter's support, weighted by
// foveation::pixel_filter_weight), through the encode's display transform and sRGB.
foveation::ImageRgb stripes_truth(const FoveartEyeView& view) {
  const foveation::EyeFrustum f = foveation::eye_frustum(view);
  const foveation::EyePose pose = foveation::eye_pose(view);
  foveation::ImageRgb truth{int(kViewW), int(kViewH)};
  const foveation::DisplayTransform display;
  for (uint32_t y = 0; y < kViewH; ++y)
    for (uint32_t x = 0; x < kViewW; ++x) {
      glm::vec3 sum(0.0f);
      float weight = 0.0f;
      for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i) {
          const glm::vec2 offset(-1.25f + 0.5f * float(i), -1.25f + 0.5f * float(j));
          const float w = foveation::pixel_filter_weight(foveation::PixelFilter::bspline2, offset.x) *
                          foveation::pixel_filter_weight(foveation::PixelFilter::bspline2, offset.y);
          const glm::vec2 at = glm::vec2(float(x) + 0.5f, float(y) + 0.5f) + offset;
          sum += w * stripes_colour(foveation::eye_ray_direction(f, pose, at));
          weight += w;
        }
      const glm::vec3 shown = display.apply(sum / weight);
      for (int c = 0; c < 3; ++c) truth.at(int(x), int(y))[c] = foveation::linear_to_srgb(shown[c]);
    }
  return truth;
}

foveation::ImageRgb display_of(const std::vector<uint8_t>& rgba8) {
  foveation::ImageRgb image{int(kViewW), int(kViewH)};
  for (std::size_t p = 0; p < image.pixel_count(); ++p)
    for (std::size_t c = 0; c < 3; ++c) image.rgb[3 * p + c] = float(rgba8[4 * p + c]) / 255.0f;
  return image;
}

// A track's flicker as the lab measures it (eval::TemporalError): along the
// motion, each frame's error against the truth less the last frame's error
// warped to where its surface is now (history_reprojection.hpp, as
// eval/motion_sequence.cpp tracks it), and at fixed pixels.
struct FlickerTrack {
  eval::TemporalError error;
  foveation::ImageRgb warped;
  std::vector<std::uint8_t> valid;
  // The sky lies at infinity: its error warps by the rotation alone (no depth).
  void add(const foveation::ImageRgb& image, const foveation::ImageRgb& truth, const metrics::EccentricityMap& map,
           const eval::MotionFrame* previous, const eval::MotionFrame& now, foveation::Executor& executor) {
    eval::TrackedPrevious tracked;
    if (previous != nullptr) {
      const std::vector<float> no_depth;
      foveation::reproject_history(error.previous_error(), no_depth, previous->view, now.view, no_depth, warped, valid,
                                   executor);
      tracked = {&warped, &valid};
    }
    error.add_frame(image, truth, map, &tracked);
  }
};

// Along the scripted motion, the device-traced render cache flickers at
// least 5x less than no history from 20 deg out (eval::kPeripheralBand), over
// the frames the lab pools (a settled history: eval::settled_frames), the
// render cache's goal as the lab's price list states it
// (peripheral_tracked_flicker_5x_lower). Both tracks trace a sky of stripes
// (stripes_engine.comp) on the device with the same jitter; the truth is
// computed (stripes_truth), so the flicker is the tracks' own.
TEST_F(DeviceRayCacheTest, DeviceTracedCacheFlickersFiveTimesLessThanNoHistoryFrom20Degrees) {
  const int settle = eval::history_settle_frames();
  const std::vector<eval::MotionFrame> frames = scripted_frames(settle + 8);
  ASSERT_EQ(frames.size(), std::size_t(settle + 8));
  engine_.answer = TestEngine::Answer::stripes;
  foveation::ViewSettings off_settings = settings_;
  off_settings.temporal = foveation::TemporalMode::off;
  foveation::FoveatedView cache_view(tables_, settings_), off_view(tables_, off_settings);
  std::string error;
  auto off_eye = gpu_->create_eye(kViewW, kViewH, &error);
  ASSERT_NE(off_eye, nullptr) << error;
  foveation::Executor executor(2);
  FlickerTrack cache, off;
  std::vector<std::uint8_t> restart;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const eval::MotionFrame& f = frames[i];
    foveation::FrameRequest req;
    req.view = f.view;
    req.gaze_px = f.gaze_px;
    req.frame_index = uint64_t(i + 1);
    req.saccade = f.saccade;
    req.blink = f.blink;
    restart.push_back(f.saccade || f.blink ? 1 : 0);
    std::vector<uint8_t> cache_rgba8, off_rgba8;
    ASSERT_TRUE(device_frame(cache_view, req, &error) && eye_->read_rgba8(&cache_rgba8, &error)) << error;
    ASSERT_TRUE(device_frame(off_view, req, &error, off_eye.get()) && off_eye->read_rgba8(&off_rgba8, &error))
        << error;
    ASSERT_EQ(eye_->device_trace_status().invalid_components, 0u) << "frame " << i;
    const foveation::ImageRgb truth = stripes_truth(f.view);
    const metrics::EccentricityMap map = metrics::eccentricity_map(f.view, f.gaze_px);
    const eval::MotionFrame* previous = i > 0 ? &frames[i - 1] : nullptr;
    cache.add(display_of(cache_rgba8), truth, map, previous, f, executor);
    off.add(display_of(off_rgba8), truth, map, previous, f, executor);
  }
  EXPECT_GT(eye_->cached_rays_after_wait(), 0u);
  const std::vector<std::uint8_t> settled = eval::settled_frames(restart, settle);
  const eval::TemporalRing c = cache.error.pooled(eval::kPeripheralBand, &settled);
  const eval::TemporalRing o = off.error.pooled(eval::kPeripheralBand, &settled);
  ASSERT_GT(c.tracked_pair_values, 0u) << "no pixel 20 deg or more from the gaze";
  std::printf("beyond 20 deg: flicker along the motion %.5f (no history) / %.5f (render cache) = %.2fx; "
              "at fixed pixels %.5f / %.5f = %.2fx\n",
              o.flicker_tracked_rms, c.flicker_tracked_rms, o.flicker_tracked_rms / c.flicker_tracked_rms,
              o.flicker_rms, c.flicker_rms, o.flicker_rms / c.flicker_rms);
  EXPECT_GE(o.flicker_tracked_rms, 5.0 * c.flicker_tracked_rms);
}

}  // namespace
}  // namespace foveart::gpu
