// gpu_engine::CallbackAdapter against engine::Tracer through the same C
// contract (FoveartTraceRaysFn): the same batches give the same radiance and
// depth per ray, from explicit rays and from view + sample_px; bad batches fail
// with FOVEART_RESULT_ERROR_INVALID_ARGUMENT; concurrent callers are serialised;
// synchronization validation stays silent. Runs on lavapipe.
#include <gpu_engine/callback_adapter.hpp>

#include <engine/default_scene.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/eye_rays.hpp>

#include "icd_pin.h"
#include "ray_agreement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace {

using foveart::gpu_engine::CallbackAdapter;
using foveart::gpu_engine::CallbackAdapterOptions;
using foveart::gpu_engine::testing::Agreement;
using foveart::gpu_engine::testing::compare;
using foveart::gpu_engine::testing::expect_agreement;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Engines {
  std::unique_ptr<foveart::engine::Tracer> cpu;
  std::unique_ptr<CallbackAdapter> gpu;
  std::string gpu_error;
  FoveartEyeView view{};
  Engines() {
    const foveart::engine::Scene scene = foveart::engine::make_default_scene();
    view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene));
    cpu = foveart::engine::Tracer::create(scene);
    CallbackAdapterOptions options;
    options.prefer_cpu = true;  // lavapipe: the same device on every machine
    options.validate = true;
    gpu = CallbackAdapter::create(scene, options, &gpu_error);
    foveart::sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
    if (gpu)
      std::printf("[ device ] %s, validation %s\n", gpu->device_name().c_str(),
                  gpu->validated() ? "on (synchronization)" : "off (layer not installed)");
  }
};

Engines& engines() {
  static Engines e;
  return e;
}

#define REQUIRE_GPU()                                                                             \
  do {                                                                                            \
    if (!engines().gpu) GTEST_SKIP() << "no Vulkan device: " << engines().gpu_error;              \
  } while (0)

// A batch's inputs and outputs.
struct Batch {
  std::vector<float> origins, directions, sample_px, rgb, depth;
  FoveartRayBatch b{};
  Batch(const FoveartEyeView& view, size_t n, bool explicit_rays, uint32_t seed = 12345u) {
    const foveart::foveation::EyeFrustum f = foveart::foveation::eye_frustum(view);
    const foveart::foveation::EyePose pose = foveart::foveation::eye_pose(view);
    uint32_t state = seed;
    auto next = [&] {
      state = state * 1664525u + 1013904223u;
      return static_cast<float>(state >> 8) / 16777216.0f;
    };
    for (size_t i = 0; i < n; ++i) {
      const glm::vec2 px(next() * static_cast<float>(view.width_px), next() * static_cast<float>(view.height_px));
      sample_px.insert(sample_px.end(), {px.x, px.y});
      const glm::vec3 d = foveart::foveation::eye_ray_direction(f, pose, px);
      origins.insert(origins.end(), {pose.position_m.x, pose.position_m.y, pose.position_m.z});
      directions.insert(directions.end(), {d.x, d.y, d.z});
    }
    rgb.assign(3 * n, kNaN);
    depth.assign(n, kNaN);
    b.type = FOVEART_TYPE_RAY_BATCH;
    b.size = sizeof(FoveartRayBatch);
    b.view = &view;
    b.ray_count = static_cast<uint32_t>(n);
    b.origins_m = explicit_rays ? origins.data() : nullptr;
    b.directions = explicit_rays ? directions.data() : nullptr;
    b.sample_px = sample_px.data();
    b.out_rgb = rgb.data();
    b.out_depth_m = depth.data();
  }
  Batch(const Batch&) = delete;
  Batch& operator=(const Batch&) = delete;
};

// Per-ray agreement as tests/engine/gpu_tracer_test.cpp measures it, with its
// tolerances (ray_agreement.hpp): rgb and depth per ray.
std::vector<glm::vec4> rgb_depth(const Batch& b) {
  std::vector<glm::vec4> out(b.depth.size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = glm::vec4(b.rgb[3 * i], b.rgb[3 * i + 1], b.rgb[3 * i + 2], b.depth[i]);
  return out;
}

Agreement compare(const Batch& gpu, const Batch& cpu) { return compare(rgb_depth(gpu), rgb_depth(cpu)); }

// Validation heard the adapter's device (layer enabled, messenger registered:
// vulkan-validationlayers is a dependency, scripts/setup.sh) and reported nothing.
void expect_no_validation_errors() {
  ASSERT_TRUE(engines().gpu->validated())
      << "validation is not active: VK_LAYER_KHRONOS_validation missing (vulkan-validationlayers) or no messenger";
  const auto errors = engines().gpu->validation_errors();
  EXPECT_TRUE(errors.empty()) << errors.size() << " errors, the first: " << (errors.empty() ? "" : errors.front());
}

TEST(GpuCallbackAdapter, ExplicitRaysAgreeWithTheCpuEnginePerRay) {
  REQUIRE_GPU();
  Engines& e = engines();
  Batch cpu(e.view, 4096, true), gpu(e.view, 4096, true);
  const foveart::engine::RayCounts c0 = e.cpu->counts(), g0 = e.gpu->counts();
  ASSERT_EQ(foveart_engine_trace_rays(e.cpu.get(), &cpu.b), FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(foveart_gpu_engine_trace_rays(e.gpu.get(), &gpu.b), FOVEART_RESULT_SUCCESS);
  expect_agreement(compare(gpu, cpu), "explicit rays");
  // Every ray has a colour; misses have +INFINITY depth as the CPU's.
  EXPECT_TRUE(std::all_of(gpu.rgb.begin(), gpu.rgb.end(), [](float v) { return std::isfinite(v) && v >= 0.0f; }));
  EXPECT_TRUE(std::any_of(gpu.depth.begin(), gpu.depth.end(), [](float d) { return std::isinf(d) && d > 0; }));
  // The same rays per effect (the shader's counters against Embree's kernel).
  const foveart::engine::RayCounts c1 = e.cpu->counts(), g1 = e.gpu->counts();
  EXPECT_EQ(g1.primary - g0.primary, 4096u);
  EXPECT_EQ(c1.primary - c0.primary, 4096u);
  auto near = [](uint64_t a, uint64_t b) { return std::fabs(double(a) - double(b)) <= 0.01 * double(std::max(a, b)) + 2; };
  EXPECT_TRUE(near(g1.shadow - g0.shadow, c1.shadow - c0.shadow));
  EXPECT_TRUE(near(g1.reflection - g0.reflection, c1.reflection - c0.reflection));
  EXPECT_TRUE(near(g1.refraction - g0.refraction, c1.refraction - c0.refraction));
  expect_no_validation_errors();
}

TEST(GpuCallbackAdapter, ViewAndSamplePositionsAgreeWithTheCpuEngineAndGrowTheBuffers) {
  REQUIRE_GPU();
  Engines& e = engines();
  // Null origins/directions: the rays come from view + sample_px. 10000 rays grow
  // the staging buffers past their first size.
  Batch cpu(e.view, 10000, false, 777u), gpu(e.view, 10000, false, 777u);
  ASSERT_EQ(foveart_engine_trace_rays(e.cpu.get(), &cpu.b), FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(foveart_gpu_engine_trace_rays(e.gpu.get(), &gpu.b), FOVEART_RESULT_SUCCESS);
  expect_agreement(compare(gpu, cpu), "view + sample_px");
  // The explicit rays of the same screen positions give the same answer.
  Batch gpu_explicit(e.view, 10000, true, 777u);
  ASSERT_EQ(foveart_gpu_engine_trace_rays(e.gpu.get(), &gpu_explicit.b), FOVEART_RESULT_SUCCESS);
  expect_agreement(compare(gpu_explicit, gpu), "explicit against view rays, both GPU");
  expect_no_validation_errors();
}

TEST(GpuCallbackAdapter, InvalidRaysAreBlackWithNoDepthAsOnTheCpu) {
  REQUIRE_GPU();
  Engines& e = engines();
  Batch cpu(e.view, 64, true), gpu(e.view, 64, true);
  for (Batch* b : {&cpu, &gpu}) {
    b->directions[3 * 5 + 0] = b->directions[3 * 5 + 1] = b->directions[3 * 5 + 2] = 0.0f;  // zero direction
    b->origins[3 * 9 + 1] = kNaN;                                                          // bad origin
    for (int k = 0; k < 3; ++k) b->directions[3 * 20 + k] *= 3.0f;  // not unit: normalised as on the CPU
  }
  ASSERT_EQ(foveart_engine_trace_rays(e.cpu.get(), &cpu.b), FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(foveart_gpu_engine_trace_rays(e.gpu.get(), &gpu.b), FOVEART_RESULT_SUCCESS);
  for (int r : {5, 9}) {
    EXPECT_EQ(gpu.rgb[3 * r], 0.0f);
    EXPECT_EQ(gpu.rgb[3 * r + 1], 0.0f);
    EXPECT_EQ(gpu.rgb[3 * r + 2], 0.0f);
    EXPECT_TRUE(std::isnan(gpu.depth[r]));
  }
  const Agreement a = compare(gpu, cpu);
  EXPECT_EQ(a.within, 1.0) << "max error " << a.max_error;
  EXPECT_EQ(a.depth_off, 0u);
}

TEST(GpuCallbackAdapter, ABatchWithoutDepthLeavesItAlone) {
  REQUIRE_GPU();
  Engines& e = engines();
  Batch gpu(e.view, 128, true);
  gpu.b.size = static_cast<uint32_t>(offsetof(FoveartRayBatch, out_depth_m));  // an older producer
  ASSERT_EQ(foveart_gpu_engine_trace_rays(e.gpu.get(), &gpu.b), FOVEART_RESULT_SUCCESS);
  EXPECT_TRUE(std::all_of(gpu.depth.begin(), gpu.depth.end(), [](float d) { return std::isnan(d); }));
  EXPECT_TRUE(std::all_of(gpu.rgb.begin(), gpu.rgb.end(), [](float v) { return std::isfinite(v); }));
}

TEST(GpuCallbackAdapter, BadBatchesAreInvalidArguments) {
  REQUIRE_GPU();
  Engines& e = engines();
  CallbackAdapter* a = e.gpu.get();
  Batch ok(e.view, 16, true);
  EXPECT_EQ(foveart_gpu_engine_trace_rays(nullptr, &ok.b), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(foveart_gpu_engine_trace_rays(a, nullptr), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  auto expect_invalid = [&](auto change, const char* what) {
    Batch b(e.view, 16, true);
    change(b.b);
    EXPECT_EQ(foveart_gpu_engine_trace_rays(a, &b.b), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << what;
    EXPECT_TRUE(std::isnan(b.rgb[0])) << what << ": nothing written";
  };
  expect_invalid([](FoveartRayBatch& b) { b.type = FOVEART_TYPE_EYE_VIEW; }, "wrong type");
  expect_invalid([](FoveartRayBatch& b) { b.size = 8; }, "too small");
  expect_invalid([](FoveartRayBatch& b) { b.out_rgb = nullptr; }, "no out_rgb");
  expect_invalid([](FoveartRayBatch& b) { b.origins_m = nullptr; b.sample_px = nullptr; }, "no rays");
  expect_invalid([](FoveartRayBatch& b) { b.directions = nullptr; b.view = nullptr; }, "no view");
  FoveartEyeView bad_view = e.view;
  bad_view.width_px = 0;
  expect_invalid([&](FoveartRayBatch& b) { b.origins_m = nullptr; b.view = &bad_view; }, "empty view");
  Batch empty(e.view, 0, true);
  EXPECT_EQ(foveart_gpu_engine_trace_rays(a, &empty.b), FOVEART_RESULT_SUCCESS);
  // Still working after the refusals.
  EXPECT_EQ(foveart_gpu_engine_trace_rays(a, &ok.b), FOVEART_RESULT_SUCCESS);
  EXPECT_TRUE(std::isfinite(ok.rgb[0]));
}

TEST(GpuCallbackAdapter, ConcurrentCallersGetTheirOwnColours) {
  REQUIRE_GPU();
  Engines& e = engines();
  constexpr int kThreads = 4;
  std::vector<std::unique_ptr<Batch>> alone, together;
  for (int t = 0; t < kThreads; ++t) {
    alone.push_back(std::make_unique<Batch>(e.view, 1500 + 100 * t, t % 2 == 0, 1000u + t));
    together.push_back(std::make_unique<Batch>(e.view, 1500 + 100 * t, t % 2 == 0, 1000u + t));
    ASSERT_EQ(foveart_gpu_engine_trace_rays(e.gpu.get(), &alone.back()->b), FOVEART_RESULT_SUCCESS);
  }
  std::vector<int32_t> status(kThreads, -100);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int rep = 0; rep < 3; ++rep) status[t] = foveart_gpu_engine_trace_rays(e.gpu.get(), &together[t]->b);
    });
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ(status[t], FOVEART_RESULT_SUCCESS);
    EXPECT_EQ(together[t]->rgb, alone[t]->rgb) << "thread " << t;
  }
  expect_no_validation_errors();
}

TEST(GpuCallbackAdapter, NamesItsDevice) {
  REQUIRE_GPU();
  EXPECT_FALSE(engines().gpu->device_name().empty());
  EXPECT_EQ(engines().gpu->effects(), engines().cpu->effects());
}

}  // namespace
