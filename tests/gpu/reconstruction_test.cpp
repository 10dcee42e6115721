// The GPU reconstruction (shaders/, gpu/) against its CPU
// reference, on a hardware GPU where the machine has one (GpuMatchesCpu's
// needs_real_gpu cases, registered only there) and on lavapipe: the same frames of foveation::FoveatedView, once
// reconstructed, accumulated and encoded by foveation (CPU) and once by the
// compute shaders, agree within one 8-bit step per channel for NN, MSM and RBF
// at k = 1/5/20, centred and corner gaze, both eyes, and the temporal history over 16 frames
// with a gaze jump. Runs under VK_LAYER_KHRONOS_validation with
// synchronization validation; any message of error severity fails the test.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <vulkan/vulkan.h>

#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/rgba8.hpp"
#include "gpu/device_stages.hpp"
#include "gpu/reconstructor.hpp"
#include "gpu/table_pack.hpp"
#include "gpu/vk_util.hpp"
#include "headless_vulkan.hpp"
#include "icd_pin.h"
#include "analytic_scene.hpp"
#include "history_kinds.hpp"

namespace foveart::gpu {
namespace {

using layer::DevicePreference;
using layer::HeadlessVulkan;
using layer::hardware_gpu_name;

using foveation::InterpMethod;

constexpr uint32_t kW = 96;
constexpr uint32_t kH = 80;

// ---- Frames ------------------------------------------------------------------

// Scale 6 puts the edge of the pixel grid (~31 px from the gaze) inside the
// 96x80 view: frames hold grid and Poisson points, and pixels at the screen
// edge reach untraced points (the invalid-tap paths).
std::shared_ptr<const foveation::ViewTables> small_tables(InterpMethod method, int k) {
  static std::map<std::pair<InterpMethod, int>, std::shared_ptr<const foveation::ViewTables>> cache;
  auto& slot = cache[{method, k}];
  if (!slot) {
    foveation::PointSetKey key;
    key.display = foveation::DisplayModel::from_fov(kW, kH, 60.0);
    key.display.scale = 6.0;
    key.seed = 1;
    foveation::InterpOptions o;
    o.method = method;
    o.k = k;
    foveation::Executor executor(2);
    slot = foveation::load_view_tables(std::nullopt, key, o, executor);
  }
  return slot;
}

// Colour by screen position and eye, with sharp edges (an RBF overshoots them
// without its clamp) and values above 1 (the encode's clamp).
int32_t scene(void*, const FoveartRayBatch* batch) {
  const float eye = float(batch->view->eye_index);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const float x = batch->sample_px[i * 2], y = batch->sample_px[i * 2 + 1];
    const bool check = (int(std::floor(x / 7.0f)) + int(std::floor(y / 5.0f))) % 2 == 0;
    batch->out_rgb[i * 3 + 0] = check ? 1.2f : 0.05f;
    batch->out_rgb[i * 3 + 1] = std::clamp(y / float(kH), 0.0f, 1.0f) * (0.5f + 0.5f * eye);
    batch->out_rgb[i * 3 + 2] = 0.5f + 0.5f * std::sin(x * 0.4f + eye);
  }
  return FOVEART_RESULT_SUCCESS;
}

foveation::FrameRequest eye_request(uint32_t eye, glm::vec2 gaze_px, uint64_t frame_index) {
  foveation::FrameRequest r;
  foveation::EyePose pose;
  pose.position_m = {eye == 0 ? -0.032f : 0.032f, 1.6f, 0.0f};
  r.view = foveation::make_eye_view(eye, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
  r.frame_index = frame_index;
  r.gaze_px = gaze_px;
  return r;
}

struct Difference {
  int max_step = 0;
  std::size_t bytes_differing = 0;
};

Difference compare(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  Difference d;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    const int step = std::abs(int(a[i]) - int(b[i]));
    d.max_step = std::max(d.max_step, step);
    d.bytes_differing += step != 0;
  }
  return d;
}

class GpuReconstruction : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    for (auto& v : vulkans_) v.reset();
  }
  // The device a test runs on: lavapipe, unless a parameterised suite says otherwise.
  virtual DevicePreference preference() const { return DevicePreference::cpu; }
  void SetUp() override {
    const DevicePreference preference_now = preference();
    std::unique_ptr<HeadlessVulkan>& slot = vulkans_[preference_now == DevicePreference::cpu ? 1 : 0];
    if (slot == nullptr) {
      slot = std::make_unique<HeadlessVulkan>(preference_now, true);
      sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
    }
    vulkan_ = slot.get();
    ASSERT_TRUE(vulkan_->ok()) << "no Vulkan device (mesa-vulkan-drivers brings lavapipe)";
    if (preference_now == DevicePreference::hardware_gpu) {  // registered only where the probe found one
      ASSERT_FALSE(vulkan_->is_cpu()) << "a needs_real_gpu case got " << vulkan_->name();
    }
    if (preference_now == DevicePreference::cpu) {
      ASSERT_TRUE(vulkan_->is_cpu()) << "no lavapipe device (mesa-vulkan-drivers); found " << vulkan_->name();
    }
    ASSERT_TRUE(vulkan_->validated()) << "VK_LAYER_KHRONOS_validation missing (vulkan-validationlayers)";
    std::string error;
    gpu_ = Reconstructor::create(vulkan_->device(), &error);
    ASSERT_NE(gpu_, nullptr) << error;
  }
  void TearDown() override {
    gpu_.reset();
    if (vulkan_ != nullptr && vulkan_->ok()) {
      const auto errors = vulkan_->errors();
      EXPECT_TRUE(errors.empty()) << errors.size() << " validation error(s), the first: " << errors.front();
    }
  }

  // Renders `frames` frames with both paths; returns the largest difference
  // over all frames. request_of(i) is frame i's request, traced by `trace`.
  template <class RequestFn>
  Difference run(InterpMethod method, int k, bool temporal, int frames, RequestFn request_of,
                 std::size_t max_chunk_bytes = 0, std::vector<std::vector<uint8_t>>* gpu_frames = nullptr,
                 uint64_t* invalid_paths = nullptr, FoveartTraceRaysFn trace = scene, void* user = nullptr,
                 uint64_t* reprojected_frames = nullptr, std::vector<std::size_t>* cached_rays = nullptr,
                 std::vector<std::size_t>* gpu_cached_rays = nullptr) {
    const auto tables = small_tables(method, k);
    foveation::ViewSettings settings;
    settings.rays_per_point = rays_per_point_;
    settings.temporal = !temporal ? foveation::TemporalMode::off : foveation::test::mode_of(history_kind_);
    settings.new_jitter_each_frame = temporal;
    settings.temporal_options.mean_while_young = mean_while_young_;
    settings.pixel_filter = pixel_filter_;
    const auto history = [&] {
      return temporal ? foveation::test::make_history(history_kind_, *tables, settings) : nullptr;
    };
    // Both sides' stage sets, run by the one driver (FoveatedView) into their resources.
    foveation::FoveatedView cpu_view(tables, settings, foveation::make_cpu_stages(tables, settings, history()));
    foveation::FoveatedView gpu_view(tables, settings, make_device_stages(tables, settings, {}, history()));
    std::string error;
    const auto gpu_tables = gpu_->upload_tables(tables, &error, max_chunk_bytes);
    EXPECT_NE(gpu_tables, nullptr) << error;
    auto gpu_eye = gpu_->create_eye(kW, kH, &error);
    EXPECT_NE(gpu_eye, nullptr) << error;
    if (gpu_tables == nullptr || gpu_eye == nullptr) return {255, 0};
    foveation::Executor executor(2);
    Difference worst;
    for (int i = 0; i < frames; ++i) {
      const foveation::FrameRequest req = request_of(i);
      std::vector<uint8_t> expected(std::size_t(kW) * kH * 4);
      foveation::HostFrame host;
      host.rgba8 = expected.data();
      host.display = display_;
      const auto cpu = cpu_view.render(req, trace, user, host, executor);
      DeviceFrame device;
      device.eye = gpu_eye.get();
      device.tables = gpu_tables.get();
      device.slot = uint32_t(i) % kFrameSlots;
      device.display = display_;
      foveation::FrameResult gpu;
      EXPECT_TRUE(gpu_->submit_and_wait(
          [&](VkCommandBuffer cb) {
            device.cb = cb;
            gpu = gpu_view.render(req, trace, user, device, executor);
            return gpu.ok();
          },
          &error))
          << error << gpu.message;
      if (reprojected_frames != nullptr) *reprojected_frames += gpu_view.hand_off().temporal.history_view ? 1 : 0;
      if (cached_rays != nullptr) cached_rays->push_back(cpu_view.cached_rays());
      EXPECT_TRUE(cpu.ok() && gpu.ok()) << cpu.message << gpu.message;
      EXPECT_EQ(cpu.temporal_reset, gpu.temporal_reset) << "frame " << i;
      if (invalid_paths != nullptr) *invalid_paths += cpu.gather.renormalized + cpu.gather.nearest_valid + cpu.gather.fallback;

      StageTimes times;
      EXPECT_TRUE(gpu_eye->stage_times(&times));  // lavapipe has timestamps
      if (gpu_cached_rays != nullptr) gpu_cached_rays->push_back(gpu_eye->cached_rays_after_wait());
      std::vector<uint8_t> actual;
      EXPECT_TRUE(gpu_eye->read_rgba8(&actual, &error)) << error;
      EXPECT_EQ(actual.size(), expected.size());
      const Difference d = compare(expected, actual);
      worst.max_step = std::max(worst.max_step, d.max_step);
      worst.bytes_differing = std::max(worst.bytes_differing, d.bytes_differing);
      if (gpu_frames != nullptr) gpu_frames->push_back(std::move(actual));
    }
    return worst;
  }

  static std::unique_ptr<HeadlessVulkan> vulkans_[2];  // [0] hardware GPU, [1] lavapipe; made on first use
  HeadlessVulkan* vulkan_ = nullptr;                   // this test's
  std::unique_ptr<Reconstructor> gpu_;
  int rays_per_point_ = 1;  // for run()'s views
  bool mean_while_young_ = false;  // for run()'s views: TemporalOptions::mean_while_young
  foveation::test::HistoryKind history_kind_ = foveation::test::HistoryKind::reproject;  // for run()'s views
  foveation::PixelFilter pixel_filter_ = foveation::PixelFilter::box;
  foveation::DisplayTransform display_;  // both paths' exposure and curve
};
std::unique_ptr<HeadlessVulkan> GpuReconstruction::vulkans_[2];

// The display transform runs in the encode shader as on the CPU, for every
// curve, and with an exposure that pushes most of the image into the roll-off.
TEST_F(GpuReconstruction, DisplayTransformMatchesTheCpuForEveryCurve) {
  std::vector<std::vector<uint8_t>> frames;
  for (const foveation::DisplayTransform& d :
       {foveation::DisplayTransform{1.0f, foveation::ToneMap::none},
        foveation::DisplayTransform{4.0f, foveation::ToneMap::pbr_neutral},
        foveation::DisplayTransform{4.0f, foveation::ToneMap::aces}}) {
    display_ = d;
    const Difference diff =
        run(InterpMethod::msm, 5, false, 1, [](int) { return eye_request(0, glm::vec2(48, 40), 1); }, 0, &frames);
    EXPECT_LE(diff.max_step, 1) << foveation::tone_map_name(d.tone_map) << ": " << diff.bytes_differing
                                << " bytes differ";
  }
  ASSERT_EQ(frames.size(), 3u);
  // Each curve changed the image: the transform is not skipped.
  EXPECT_GT(compare(frames[0], frames[1]).bytes_differing, frames[0].size() / 4);
  EXPECT_GT(compare(frames[1], frames[2]).bytes_differing, frames[0].size() / 4);
}

struct Case {
  InterpMethod method;
  int k;
  DevicePreference device;
};

class GpuMatchesCpu : public GpuReconstruction, public ::testing::WithParamInterface<Case> {
 protected:
  DevicePreference preference() const override { return GetParam().device; }
};

// Every method and k on lavapipe (CI), and on a hardware GPU where the machine
// has one: those cases are registered (and listed by ctest) only there, probed
// when the tests are registered, rather than skipped everywhere else.
std::vector<Case> gpu_matches_cpu_cases() {
  std::vector<Case> cases;
  std::vector<DevicePreference> devices{DevicePreference::cpu};
  if (!hardware_gpu_name(sim::pin_loaded_vulkan_icds_and_layers).empty()) {
    devices.push_back(DevicePreference::hardware_gpu);
  }
  for (DevicePreference device : devices) {
    for (auto [method, k] : {std::pair{InterpMethod::nearest, 1}, std::pair{InterpMethod::msm, 1}, std::pair{InterpMethod::msm, 5},
                             std::pair{InterpMethod::msm, 20}, std::pair{InterpMethod::rbf, 1},
                             std::pair{InterpMethod::rbf, 5}, std::pair{InterpMethod::rbf, 20}}) {
      cases.push_back({method, k, device});
    }
  }
  return cases;
}

TEST_P(GpuMatchesCpu, WithinOneStepCentredAndCornerGazeBothEyes) {
  const Case c = GetParam();
  uint64_t invalid_paths = 0;
  for (uint32_t eye : {0u, 1u}) {
    for (glm::vec2 gaze : {glm::vec2(48, 40), glm::vec2(2, 3), glm::vec2(93, 77)}) {
      const Difference d =
          run(c.method, c.k, false, 1, [&](int i) { return eye_request(eye, gaze, uint64_t(i + 1)); }, 0, nullptr,
              &invalid_paths);
      EXPECT_LE(d.max_step, 1) << "eye " << eye << " gaze " << gaze.x << "," << gaze.y << ": " << d.bytes_differing
                               << " bytes differ";
    }
  }
  // The screen edges reached untraced points: the GPU's invalid-tap paths ran too.
  EXPECT_GT(invalid_paths, 0u);
}

TEST_P(GpuMatchesCpu, TemporalOver16FramesWithAGazeJump) {
  const Case c = GetParam();
  for (uint32_t eye : {0u, 1u}) {
    // Drift at the centre, a jump to the corner at frame 8 (the history restarts), drift there.
    const Difference d = run(c.method, c.k, true, 16, [&](int i) {
      const glm::vec2 gaze = i < 8 ? glm::vec2(48.0f + float(i % 3), 40.0f) : glm::vec2(10.0f + float(i % 2), 8.0f);
      return eye_request(eye, gaze, uint64_t(i + 1));
    });
    EXPECT_LE(d.max_step, 1) << "eye " << eye << ": " << d.bytes_differing << " bytes differ";
  }
}

// A young history's mean (TemporalOptions::mean_while_young): after each restart
// (the first frame, the jump at frame 8) the GPU blends frame k with the CPU's
// weight 1/k until it reaches alpha.
TEST_P(GpuMatchesCpu, TemporalYoungHistoryMeanBlendsLikeTheCpu) {
  const Case c = GetParam();
  mean_while_young_ = true;
  const Difference d = run(c.method, c.k, true, 16, [&](int i) {
    const glm::vec2 gaze = i < 8 ? glm::vec2(48.0f + float(i % 3), 40.0f) : glm::vec2(10.0f + float(i % 2), 8.0f);
    return eye_request(0, gaze, uint64_t(i + 1));
  });
  EXPECT_LE(d.max_step, 1) << d.bytes_differing << " bytes differ";
}

// More rays per point blend with a larger weight (temporal_options_for_rays): the
// GPU blends with the CPU's.
TEST_P(GpuMatchesCpu, TemporalAtFourRaysPerPointBlendsLikeTheCpu) {
  const Case c = GetParam();
  rays_per_point_ = 4;
  const Difference d = run(c.method, c.k, true, 8, [&](int i) {
    return eye_request(0, glm::vec2(48.0f + float(i % 3), 40.0f), uint64_t(i + 1));
  });
  EXPECT_LE(d.max_step, 1) << d.bytes_differing << " bytes differ";
}

// The head turns and steps sideways every frame in front of a near bar and a
// far wall, the engine returning depth: the GPU reprojects the history as the
// CPU does (rotation + parallax, disocclusion), within one 8-bit step.
int32_t analytic(void* user, const FoveartRayBatch* batch) {
  const auto* scene_of = static_cast<const foveation::test::AnalyticScene*>(user);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const float* o = batch->origins_m + 3 * i;
    const float* d = batch->directions + 3 * i;
    float depth = 0.0f;
    const glm::vec3 c = scene_of->shade({o[0], o[1], o[2]}, {d[0], d[1], d[2]}, &depth);
    for (int j = 0; j < 3; ++j) batch->out_rgb[3 * i + j] = c[j];
    batch->out_depth_m[i] = depth;
  }
  return FOVEART_RESULT_SUCCESS;
}

TEST_P(GpuMatchesCpu, TemporalReprojectsAMovingHeadLikeTheCpu) {
  const Case c = GetParam();
  foveation::test::AnalyticScene bar_and_wall;
  for (uint32_t eye : {0u, 1u}) {
    uint64_t reprojected = 0;
    const Difference d = run(
        c.method, c.k, true, 16,
        [&](int i) {
          foveation::EyePose pose;
          pose.position_m = {(eye == 0 ? -0.032f : 0.032f) + 0.01f * float(i), 1.6f, 0.0f};
          pose.orientation = glm::angleAxis(glm::radians(-0.4f * float(i)), glm::vec3(0, 1, 0));
          foveation::FrameRequest r;
          r.view = foveation::make_eye_view(eye, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
          r.frame_index = uint64_t(i + 1);
          r.gaze_px = {48, 40};
          return r;
        },
        0, nullptr, nullptr, analytic, &bar_and_wall, &reprojected);
    EXPECT_EQ(reprojected, 15u) << "every frame after the first reprojects";
    EXPECT_LE(d.max_step, 1) << "eye " << eye << ": " << d.bytes_differing << " bytes differ";
  }
}

// The render cache (TemporalMode::rays) on the GPU against the CPU's,
// while the head turns and steps in front of a near bar and a far wall and
// a saccade moves the gaze (frame 9: a restart, unless kept through): the same
// rays kept every frame, the same frames within one 8-bit step, with both
// pixel filters, the pixel grid and the Poisson periphery beyond it.
TEST_P(GpuMatchesCpu, RayCacheKeepsAndFiltersTheRaysLikeTheCpu) {
  const Case c = GetParam();
  foveation::test::AnalyticScene bar_and_wall;
  for (const auto filter : {foveation::PixelFilter::box, foveation::PixelFilter::bspline2}) {
    for (const bool kept_through : {false, true}) {
      pixel_filter_ = filter;
      history_kind_ = kept_through ? foveation::test::HistoryKind::ray_cache_kept : foveation::test::HistoryKind::ray_cache;
      std::vector<std::size_t> cpu_rays, gpu_rays;
      const Difference d = run(
          c.method, c.k, true, 12,
          [&](int i) {
            foveation::EyePose pose;
            pose.position_m = {0.01f * float(i), 1.6f, 0.0f};
            pose.orientation = glm::angleAxis(glm::radians(-0.4f * float(i)), glm::vec3(0, 1, 0));
            foveation::FrameRequest r;
            r.view = foveation::make_eye_view(0, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
            r.frame_index = uint64_t(i + 1);
            r.gaze_px = i < 9 ? glm::vec2(48, 40) : glm::vec2(30, 50);
            r.saccade = i == 9;
            return r;
          },
          0, nullptr, nullptr, analytic, &bar_and_wall, nullptr, &cpu_rays, &gpu_rays);
      const std::string what = std::string(filter == foveation::PixelFilter::box ? "box" : "bspline2") +
                               (kept_through ? ", kept through the saccade" : "");
      EXPECT_LE(d.max_step, 1) << what << ": " << d.bytes_differing << " bytes differ";
      EXPECT_EQ(gpu_rays, cpu_rays) << what;
      ASSERT_EQ(cpu_rays.size(), 12u);
      EXPECT_GT(cpu_rays[7], 3 * cpu_rays[0]) << what << ": the cache grows over the frames";
      if (!kept_through) {
        EXPECT_LT(cpu_rays[9], cpu_rays[8]) << what << ": the saccade restarts it";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, GpuMatchesCpu, ::testing::ValuesIn(gpu_matches_cpu_cases()),
                         [](const auto& param_info) {
                           const char* m = param_info.param.method == InterpMethod::nearest    ? "nn"
                                           : param_info.param.method == InterpMethod::msm ? "msm"
                                                                                    : "rbf";
                           const char* device =
                               param_info.param.device == DevicePreference::hardware_gpu ? "needs_real_gpu" : "lavapipe";
                           return std::string(device) + "_" + m + "_k" + std::to_string(param_info.param.k);
                         });

// The render cache's buffers grow with the rays a frame holds, up to the
// device's maxStorageBufferRange (here made small) and not past it: where the
// host's bound on the kept rays (the rays of the frames within the age limit)
// would not fit, the cache keeps fewer frames, so the rays it keeps stay
// within the range while the CPU's (no such limit) outgrow it; a frame whose
// new rays alone do not fit fails with a message that says so and records nothing.
TEST_F(GpuReconstruction, RayCacheKeepsFewerFramesAtTheDeviceLimitAndRefusesAFrameBeyondIt) {
  foveation::ViewSettings settings;
  settings.temporal = foveation::TemporalMode::rays;
  settings.new_jitter_each_frame = true;
  foveation::FoveatedView cpu_view(small_tables(InterpMethod::msm, 5), settings);  // the CPU's cache, unlimited
  settings.reconstruct_on_cpu = false;
  foveation::FoveatedView view(small_tables(InterpMethod::msm, 5), settings);
  std::string error;
  const Device device = vulkan_->device();
  auto pipelines = RayCachePipelines::create(device.device, &error);
  ASSERT_NE(pipelines, nullptr) << error;
  VkPhysicalDeviceMemoryProperties memory{};
  vkGetPhysicalDeviceMemoryProperties(device.physical_device, &memory);
  VkBuffer current = VK_NULL_HANDLE;
  VkDeviceMemory current_memory = VK_NULL_HANDLE;
  ASSERT_TRUE(create_bound_buffer(device.device, memory, VkDeviceSize{kW} * kH * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &current, &current_memory, nullptr, &error))
      << error;
  constexpr std::size_t kLimitRays = 40000;  // 32-byte anchors: about 6 frames of this view's rays
  foveation::Executor executor(2);
  auto frame_of = [&](const foveation::FrameResult& result) {
    RayCacheFrame frame;
    frame.rays = &view.hand_off().traced->rays;
    frame.pixels = view.hand_off().temporal.ray_pixels;
    frame.restart = result.ray_cache_restart;
    return frame;
  };
  {
    RayCache cache(gpu_->context(), *pipelines, current, kW, kH, kFrameSlots, kLimitRays * 32);
    std::size_t most_kept = 0, most_cpu_kept = 0;
    for (int i = 0; i < 12; ++i) {
      const foveation::FrameRequest req = eye_request(0, {48, 40}, uint64_t(i + 1));
      const auto result = view.render(req, scene, nullptr, executor);
      ASSERT_TRUE(result.ok() && cpu_view.render(req, scene, nullptr, executor).ok());
      std::string record_error;
      ASSERT_TRUE(gpu_->submit_and_wait(
          [&](VkCommandBuffer cb) {
            return cache.record(cb, frame_of(result), req.view, uint32_t(i) % kFrameSlots, executor, &record_error);
          },
          &error))
          << error << record_error;
      std::size_t kept = 0;
      ASSERT_TRUE(cache.kept_rays_after_wait(gpu_->context(), &kept, &error)) << error;
      EXPECT_LE(kept, kLimitRays) << "frame " << i;
      most_kept = std::max(most_kept, kept);
      most_cpu_kept = std::max(most_cpu_kept, cpu_view.cached_rays());
    }
    EXPECT_GT(most_cpu_kept, kLimitRays) << "the limit did not bind";
    EXPECT_GT(most_kept, kLimitRays / 4) << "the cache kept too few frames";
  }
  {
    constexpr std::size_t kTooFewRays = 1000;  // less than one frame's rays
    RayCache cache(gpu_->context(), *pipelines, current, kW, kH, kFrameSlots, kTooFewRays * 32);
    const foveation::FrameRequest req = eye_request(0, {48, 40}, 20);
    const auto result = view.render(req, scene, nullptr, executor);
    ASSERT_TRUE(result.ok());
    std::string record_error;
    EXPECT_FALSE(gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) { return cache.record(cb, frame_of(result), req.view, 0, executor, &record_error); },
        &error));
    EXPECT_NE(record_error.find("maxStorageBufferRange (32000)"), std::string::npos) << record_error;
    std::size_t kept = 1;
    ASSERT_TRUE(cache.kept_rays_after_wait(gpu_->context(), &kept, &error)) << error;
    EXPECT_EQ(kept, 0u) << "the refused frame recorded nothing";
  }
  vkDestroyBuffer(device.device, current, nullptr);
  vkFreeMemory(device.device, current_memory, nullptr);
}

// Tables cut into many small buffers give the same bits as one buffer.
TEST_F(GpuReconstruction, ChunkedTablesGiveTheSameFrame) {
  for (Case c : {Case{InterpMethod::nearest, 1, DevicePreference::cpu}, Case{InterpMethod::rbf, 20, DevicePreference::cpu}}) {
    TablePack whole;
    std::string error;
    ASSERT_TRUE(pack_tables(*small_tables(c.method, c.k), 1u << 30, &whole, &error)) << error;
    ASSERT_EQ(whole.chunks.size(), 1u);
    const std::size_t small = whole.bytes() / 6;
    std::vector<std::vector<uint8_t>> one, many;
    auto at = [](int) { return eye_request(0, glm::vec2(30, 50), 1); };
    run(c.method, c.k, false, 1, at, 0, &one);
    run(c.method, c.k, false, 1, at, small, &many);
    TablePack cut;
    ASSERT_TRUE(pack_tables(*small_tables(c.method, c.k), small, &cut, &error)) << error;
    EXPECT_GE(cut.chunks.size(), 6u);
    for (std::size_t i = 1; i < cut.chunks.size(); ++i) EXPECT_EQ(cut.chunks[i].first_row, cut.chunks[i - 1].end_row);
    ASSERT_EQ(one.size(), 1u);
    ASSERT_EQ(many.size(), 1u);
    EXPECT_EQ(one[0], many[0]);
  }
}

// One stage hierarchy: each side's set, on the other side's resources (or a
// device frame with nothing to record into), fails the frame with a clear
// message instead of writing anything.
TEST_F(GpuReconstruction, EachSidesStagesRefuseTheOtherSidesResources) {
  const auto tables = small_tables(InterpMethod::msm, 5);
  const foveation::ViewSettings settings;
  foveation::Executor executor(2);
  const foveation::FrameRequest req = eye_request(0, glm::vec2(40, 40), 1);
  foveation::FoveatedView cpu_view(tables, settings, foveation::make_cpu_stages(tables, settings));
  foveation::FoveatedView gpu_view(tables, settings, make_device_stages(tables, settings, {}));
  DeviceFrame device;
  foveation::HostFrame host;
  const auto cpu_on_device = cpu_view.render(req, scene, nullptr, device, executor);
  EXPECT_EQ(cpu_on_device.failure, foveation::FrameFailure::resources_failed);
  EXPECT_NE(cpu_on_device.message.find("runs on the host"), std::string::npos) << cpu_on_device.message;
  const auto gpu_on_host = gpu_view.render(req, scene, nullptr, host, executor);
  EXPECT_EQ(gpu_on_host.failure, foveation::FrameFailure::resources_failed);
  EXPECT_NE(gpu_on_host.message.find("records on the device"), std::string::npos) << gpu_on_host.message;
  EXPECT_EQ(gpu_on_host.rays, 0u) << "refused before the engine ran";
  const auto nothing_to_record = gpu_view.render(req, scene, nullptr, device, executor);
  EXPECT_EQ(nothing_to_record.failure, foveation::FrameFailure::resources_failed);
  EXPECT_NE(nothing_to_record.message.find("no command buffer"), std::string::npos) << nothing_to_record.message;
  EXPECT_EQ(host.output, nullptr);
  EXPECT_TRUE(cpu_view.render(req, scene, nullptr, host, executor).ok()) << "each on its own side runs";
}

TEST(Tables, RefusesWhatTheShadersCannotRead) {
  TablePack pack;
  std::string error;
  // A tile row larger than the buffer limit.
  EXPECT_FALSE(pack_tables(*small_tables(InterpMethod::msm, 5), 1024, &pack, &error));
  EXPECT_NE(error.find("one row of 8x8 canvas tiles"), std::string::npos) << error;
  // More than kMaxTableChunks buffers.
  TablePack whole;
  ASSERT_TRUE(pack_tables(*small_tables(InterpMethod::msm, 5), 1u << 30, &whole, &error));
  EXPECT_FALSE(pack_tables(*small_tables(InterpMethod::msm, 5), whole.bytes() / 18, &pack, &error));
  EXPECT_NE(error.find("more than 16 buffers"), std::string::npos) << error;
  // Plain RBF keeps a per-pixel gain.
  foveation::PointSetKey key;
  key.display = foveation::DisplayModel::from_fov(kW, kH, 60.0);
  key.display.scale = 6.0;
  foveation::InterpOptions plain;
  plain.method = InterpMethod::rbf;
  plain.k = 5;
  plain.constant_term = false;
  foveation::Executor executor(2);
  const auto tables = foveation::load_view_tables(std::nullopt, key, plain, executor);
  EXPECT_FALSE(pack_tables(*tables, 1u << 30, &pack, &error));
  EXPECT_NE(error.find("plain RBF"), std::string::npos) << error;
}

}  // namespace
}  // namespace foveart::gpu
