// GpuTracer against engine::Tracer: the same rays give the same radiance, depth
// and ray counts; the full render matches engine::render_full; bad input fails
// cleanly; synchronization validation stays silent. Runs on lavapipe.
#include <gpu_engine/gpu_tracer.hpp>
#include <gpu_engine/timestamps.hpp>

#include <engine/default_scene.hpp>
#include <engine/gltf_loader.hpp>
#include <engine/procedural_scenes.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/executor.hpp>
#include <foveation/eye_rays.hpp>

#include "gpu_trace_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

using foveart::engine::Effects;
using foveart::engine::RayCounts;
using foveart::engine::Scene;
using foveart::gpu_engine::GpuContext;
using foveart::gpu_engine::GpuTracer;
using foveart::gpu_engine::GpuTracerOptions;
using foveart::layer::DevicePreference;
using namespace foveart::gpu_engine::testing;

// A narrow memory barrier for the tests' own recordings around the engine's
// compute: host writes -> shader and indirect reads, shader writes -> host reads.
void barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
             VkAccessFlags dst_access) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

// The CPU reference: rgb and depth per ray.
std::vector<glm::vec4> trace_cpu(foveart::engine::Tracer& tracer, const Rays& rays) {
  const size_t n = rays.origin.size();
  std::vector<float> o, d, rgb(3 * n), depth(n);
  for (size_t i = 0; i < n; ++i) {
    o.insert(o.end(), {rays.origin[i].x, rays.origin[i].y, rays.origin[i].z});
    d.insert(d.end(), {rays.dir[i].x, rays.dir[i].y, rays.dir[i].z});
  }
  FoveartRayBatch b{};
  b.type = FOVEART_TYPE_RAY_BATCH;
  b.size = sizeof(b);
  b.ray_count = static_cast<uint32_t>(n);
  b.origins_m = o.data();
  b.directions = d.data();
  b.out_rgb = rgb.data();
  b.out_depth_m = depth.data();
  EXPECT_EQ(foveart_engine_trace_rays(&tracer, &b), FOVEART_RESULT_SUCCESS);
  std::vector<glm::vec4> out(n);
  for (size_t i = 0; i < n; ++i) out[i] = glm::vec4(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], depth[i]);
  return out;
}

TestGpu& gpu() {  // one validated lavapipe device for the whole suite
  static TestGpu g(DevicePreference::cpu, false);
  return g;
}

std::vector<glm::vec4> trace_gpu(GpuTracer& tracer, const Rays& r) { return trace(gpu(), tracer, r); }

#define REQUIRE_GPU()                                                 \
  do {                                                                \
    if (!gpu().vk.ok()) GTEST_SKIP() << "no Vulkan device";           \
  } while (0)

void expect_no_validation_errors() { expect_no_validation_errors(gpu()); }

std::unique_ptr<GpuTracer> make_gpu(Scene scene, const GpuTracerOptions& options = {}) {
  std::string error;
  auto t = GpuTracer::create(gpu().context(), std::move(scene), options, &error);
  EXPECT_NE(t, nullptr) << error;
  return t;
}

std::unique_ptr<foveart::engine::Tracer> make_cpu(Scene scene, Effects allowed = Effects::all()) {
  std::string error;
  foveart::engine::TracerOptions options;
  options.allowed = allowed;
  auto t = foveart::engine::Tracer::create(std::move(scene), options, &error);
  EXPECT_NE(t, nullptr) << error;
  return t;
}

// Per-ray agreement over n rays of the FOVE left eye view of `scene`.
void expect_scene_agrees(const Scene& scene, const char* what, size_t n = 4096) {
  auto g = make_gpu(scene);
  auto c = make_cpu(scene);
  ASSERT_TRUE(g && c);
  EXPECT_EQ(g->effects(), c->effects());
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), n);
  expect_agreement(compare(trace_gpu(*g, rays), trace_cpu(*c, rays)), what);
  expect_no_validation_errors();
}

// ---- agreement with engine::Tracer ------------------------------------------------

TEST(GpuTracer, DefaultSceneAgreesWithTheCpuTracerPerRay) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_default_scene();
  const Effects fx = foveart::engine::derive_effects(scene);
  ASSERT_TRUE(fx.shadows && fx.reflection && fx.refraction && fx.textures);  // every path of the kernel
  expect_scene_agrees(scene, "default scene");
}

TEST(GpuTracer, LitRoomAgreesWithTheCpuTracerPerRay) {
  REQUIRE_GPU();
  expect_scene_agrees(foveart::engine::make_lit_room(), "room (12 point lights)");
}

TEST(GpuTracer, TexturedHallAgreesWithTheCpuTracerPerRay) {
  REQUIRE_GPU();
  expect_scene_agrees(foveart::engine::make_textured_hall(), "hall (textures, spot lights)");
}

TEST(GpuTracer, TexturedGltfAgreesWithTheCpuTracerPerRay) {
  REQUIRE_GPU();
  const std::filesystem::path file = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not installed (assimp-testmodels)";
  const foveart::engine::LoadResult loaded = foveart::engine::load_gltf(file.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  ASSERT_TRUE(foveart::engine::derive_effects(*loaded.scene).textures);
  expect_scene_agrees(*loaded.scene, "BoxTextured.gltf");
}

TEST(GpuTracer, AlphaMaskCutsOutTheSameTexelsAsTheCpu) {
  REQUIRE_GPU();
  Scene s;
  s.source = "mask";
  foveart::engine::Material m;
  m.roughness = 1.0f;
  m.metallic = 0.0f;
  m.alpha_mode = foveart::engine::AlphaMode::kMask;
  m.base_color_texture = 0;
  s.materials.push_back(m);
  foveart::engine::Texture t;  // left half transparent, right half opaque
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 1)};
  t.nearest = true;
  s.textures.push_back(t);
  add_floor(s, 1.0f, 0);
  auto g = make_gpu(s);
  auto c = make_cpu(s);
  ASSERT_TRUE(g && c);
  const Rays rays = down_rays(32, 0.9f);
  const auto go = trace_gpu(*g, rays);
  const auto co = trace_cpu(*c, rays);
  size_t misses = 0;
  for (const glm::vec4& v : go) misses += std::isinf(v.w) ? 1 : 0;
  EXPECT_GT(misses, rays.origin.size() / 4);  // the transparent half is cut out
  EXPECT_LT(misses, 3 * rays.origin.size() / 4);
  expect_agreement(compare(go, co), "alpha mask");
  expect_no_validation_errors();
}

// ---- memory --------------------------------------------------------------------------

void print_memory(const char* what, const GpuTracer& t) {
  const foveart::gpu_engine::MemoryUse m = t.memory_use();
  std::printf("[ memory ] %s: device-local %llu bytes, host-visible %llu bytes, of which textures %llu bytes\n", what,
              static_cast<unsigned long long>(m.device_local_bytes),
              static_cast<unsigned long long>(m.host_visible_bytes), static_cast<unsigned long long>(m.texture_bytes));
}

// The GPU engine runs the CPU engine's scene check (engine::prepare_scene): a far scene is refused alike.
TEST(GpuTracer, RefusesTheScenesTheCpuTracerRefuses) {
  Scene scene = foveart::engine::make_default_scene();
  scene.mesh.positions[0].y = -3e9f;
  std::string cpu_error, gpu_error;
  EXPECT_EQ(foveart::engine::Tracer::create(scene, {}, &cpu_error), nullptr);
  EXPECT_EQ(GpuTracer::create(gpu().context(), scene, {}, &gpu_error), nullptr);
  EXPECT_NE(cpu_error.find("lies beyond 1e+09 m of the origin"), std::string::npos) << cpu_error;
  EXPECT_NE(gpu_error.find(cpu_error), std::string::npos) << gpu_error;
}

TEST(GpuTracer, SceneLivesInDeviceLocalMemory) {
  REQUIRE_GPU();
  auto g = make_gpu(foveart::engine::make_textured_hall());
  ASSERT_TRUE(g);
  print_memory("hall", *g);
  EXPECT_EQ(g->memory_fallback(), "");
  EXPECT_GT(g->memory_use().device_local_bytes, 0u);
  EXPECT_EQ(g->memory_use().host_visible_bytes, 0u);
  expect_no_validation_errors();
}

TEST(GpuTracer, HostVisibleFallbackRendersTheSameAndSaysSoOnce) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_textured_hall();
  GpuTracerOptions options;
  options.device_local_memory = false;  // as a device without device-local memory that fits
  auto g = make_gpu(scene, options);
  auto c = make_cpu(scene);
  ASSERT_TRUE(g && c);
  print_memory("hall, host-visible fallback", *g);
  const std::string& line = g->memory_fallback();
  std::printf("[ fallback ] %s\n", line.c_str());
  EXPECT_NE(line.find("host-visible"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos) << "one line";
  EXPECT_EQ(g->memory_use().device_local_bytes, 0u);
  EXPECT_GT(g->memory_use().host_visible_bytes, 0u);
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 4096);
  expect_agreement(compare(trace_gpu(*g, rays), trace_cpu(*c, rays)), "hall, host-visible fallback");
  expect_no_validation_errors();
}

// ---- effects and ray counts ---------------------------------------------------------

TEST(GpuTracer, RayCountsEqualTheCpuTracersOnTheDefaultScene) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_default_scene();
  auto g = make_gpu(scene);
  auto c = make_cpu(scene);
  ASSERT_TRUE(g && c);
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 4096);
  trace_gpu(*g, rays);
  trace_cpu(*c, rays);
  const RayCounts gc = g->counts(), cc = c->counts();
  std::printf("[ counts ] gpu primary %llu shadow %llu reflection %llu refraction %llu; cpu %llu %llu %llu %llu\n",
              static_cast<unsigned long long>(gc.primary), static_cast<unsigned long long>(gc.shadow),
              static_cast<unsigned long long>(gc.reflection), static_cast<unsigned long long>(gc.refraction),
              static_cast<unsigned long long>(cc.primary), static_cast<unsigned long long>(cc.shadow),
              static_cast<unsigned long long>(cc.reflection), static_cast<unsigned long long>(cc.refraction));
  EXPECT_EQ(gc.primary, 4096u);
  EXPECT_EQ(gc.primary, cc.primary);
  // Secondary counts follow the hits: the few edge rays that flip may change them by a hair.
  auto near = [](uint64_t a, uint64_t b) { return std::fabs(double(a) - double(b)) <= 0.005 * double(b) + 2.0; };
  EXPECT_GT(cc.shadow, 0u);
  EXPECT_GT(cc.reflection, 0u);
  EXPECT_GT(cc.refraction, 0u);
  EXPECT_TRUE(near(gc.shadow, cc.shadow));
  EXPECT_TRUE(near(gc.reflection, cc.reflection));
  EXPECT_TRUE(near(gc.refraction, cc.refraction));
  g->reset_counts();
  EXPECT_EQ(g->counts().total(), 0u);
  expect_no_validation_errors();
}

TEST(GpuTracer, AbsentEffectsCastNoRays) {
  REQUIRE_GPU();
  Scene s;  // one rough, opaque, untextured floor; no lights
  s.source = "plain";
  foveart::engine::Material m;
  m.roughness = 1.0f;
  m.metallic = 0.0f;
  s.materials.push_back(m);
  add_floor(s, 2.0f, 0);
  auto g = make_gpu(s);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->effects(), Effects::none());
  const Rays rays = down_rays(16, 1.5f);
  const auto out = trace_gpu(*g, rays);
  const RayCounts c = g->counts();
  EXPECT_EQ(c.primary, rays.origin.size());
  EXPECT_EQ(c.shadow, 0u);
  EXPECT_EQ(c.reflection, 0u);
  EXPECT_EQ(c.refraction, 0u);
  for (const glm::vec4& v : out) EXPECT_NEAR(v.w, 1.0f / std::fabs(glm::normalize(glm::vec3(0.1f, -1.0f, 0.05f)).y), 1e-4f);
  expect_no_validation_errors();
}

// ---- the benchmark's timestamp check (gpu_engine/timestamps.hpp) --------------------

TEST(GpuTimestamps, AQueueWithoutTimestampsOrStampsThatDoNotAdvanceAreRefusedByName) {
  using foveart::gpu_engine::timestamp_reading_problem;
  using foveart::gpu_engine::timestamp_support_problem;
  EXPECT_EQ(timestamp_support_problem("GPU X", 64, 1.0f), "");
  const std::string no_bits = timestamp_support_problem("GPU X", 0, 1.0f);
  EXPECT_NE(no_bits.find("GPU X"), std::string::npos) << no_bits;
  EXPECT_NE(no_bits.find("timestampValidBits 0"), std::string::npos) << no_bits;
  EXPECT_NE(timestamp_support_problem("GPU X", 36, 0.0f), "");
  EXPECT_EQ(timestamp_reading_problem("GPU X", 100, 250), "");
  const std::string zeros = timestamp_reading_problem("GPU X", 0, 0);
  EXPECT_NE(zeros.find("GPU X"), std::string::npos) << zeros;
  EXPECT_NE(zeros.find("read 0"), std::string::npos) << zeros;
  EXPECT_NE(timestamp_reading_problem("GPU X", 250, 250), "");
  EXPECT_NE(timestamp_reading_problem("GPU X", 250, 100), "");
}

TEST(GpuTimestamps, TheTestDevicesQueueHasThem) {
  REQUIRE_GPU();
  const GpuContext context = gpu().context();
  EXPECT_EQ(foveart::gpu_engine::timestamp_support_problem(context.physical_device, context.queue_family_index), "");
  EXPECT_NE(foveart::gpu_engine::timestamp_support_problem(context.physical_device, 1000u), "") << "no such family";
}

// ---- traversal work (GpuTracerOptions::count_work) -----------------------------------

// A floor of two triangles is one leaf under the root: every ray visits both nodes
// and tests both triangles, so the counts are exact.
TEST(GpuTracer, WorkCountersCountEachNodeAndTriangleOfAOneLeafScene) {
  REQUIRE_GPU();
  Scene s;
  s.source = "floor";  // rough, opaque, untextured, no lights: primary rays only
  foveart::engine::Material m;
  m.roughness = 1.0f;
  m.metallic = 0.0f;
  s.materials.push_back(m);
  add_floor(s, 2.0f, 0);
  GpuTracerOptions options;
  options.count_work = true;
  auto g = make_gpu(s, options);
  ASSERT_TRUE(g);
  ASSERT_EQ(g->bvh_node_count(), 2u) << "the root and one leaf";
  const Rays rays = down_rays(16, 1.5f);
  trace_gpu(*g, rays);
  const foveart::gpu_engine::WorkCounts w = g->work_counts();
  EXPECT_TRUE(w.counted);
  EXPECT_EQ(g->counts().total(), rays.origin.size());
  EXPECT_EQ(w.bvh_nodes, 2u * rays.origin.size());
  EXPECT_EQ(w.triangle_tests, 2u * rays.origin.size());
  g->reset_counts();
  EXPECT_EQ(g->work_counts().bvh_nodes, 0u);
  EXPECT_EQ(g->work_counts().triangle_tests, 0u);
  expect_no_validation_errors();
}

// On the default scene each ray's traversal visits at least the root and at most
// every node, tests at most every triangle; counting changes no colour and no
// ray count, and a tracer not asked to count leaves the counters at 0.
TEST(GpuTracer, WorkCountersBoundEachTraversalAndChangeNothing) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_default_scene();
  GpuTracerOptions options;
  options.count_work = true;
  auto counting = make_gpu(scene, options);
  auto plain = make_gpu(scene);
  ASSERT_TRUE(counting && plain);
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 4096);
  const auto a = trace_gpu(*counting, rays);
  const auto b = trace_gpu(*plain, rays);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])), 0) << "counting changed a colour";
  const RayCounts c = counting->counts();
  EXPECT_EQ(c.total(), plain->counts().total());
  EXPECT_GT(c.shadow + c.reflection + c.refraction, 0u);
  const foveart::gpu_engine::WorkCounts w = counting->work_counts();
  std::printf("[ work ] %llu rays, %llu BVH nodes (%.1f per ray of %llu), %llu triangle tests\n",
              static_cast<unsigned long long>(c.total()), static_cast<unsigned long long>(w.bvh_nodes),
              double(w.bvh_nodes) / double(c.total()), static_cast<unsigned long long>(counting->bvh_node_count()),
              static_cast<unsigned long long>(w.triangle_tests));
  EXPECT_TRUE(w.counted);
  EXPECT_GT(w.bvh_nodes, 2u * c.total()) << "rays descend below the root";
  EXPECT_LE(w.bvh_nodes, counting->bvh_node_count() * c.total());
  EXPECT_GT(w.triangle_tests, 0u);
  EXPECT_LE(w.triangle_tests, scene.mesh.triangles.size() * c.total());
  const foveart::gpu_engine::WorkCounts none = plain->work_counts();
  EXPECT_FALSE(none.counted);
  EXPECT_EQ(none.bvh_nodes + none.triangle_tests, 0u);
  expect_no_validation_errors();
}

TEST(GpuTracer, EffectsNotAllowedCastNoRaysAndMatchTheCpuKernel) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_default_scene();
  GpuTracerOptions options;
  options.allowed = Effects::none();
  auto g = make_gpu(scene, options);
  auto c = make_cpu(scene, Effects::none());
  ASSERT_TRUE(g && c);
  EXPECT_EQ(g->effects(), Effects::none());
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 2048);
  expect_agreement(compare(trace_gpu(*g, rays), trace_cpu(*c, rays)), "default scene, primary only");
  const RayCounts gc = g->counts();
  EXPECT_EQ(gc.primary, 2048u);
  EXPECT_EQ(gc.shadow + gc.reflection + gc.refraction, 0u);
  expect_no_validation_errors();
}

TEST(GpuTracer, TracesOnlyTheCountedRaysAndFollowsNewBuffers) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_lit_room();
  auto g = make_gpu(scene);
  auto c = make_cpu(scene);
  ASSERT_TRUE(g && c);
  const FoveartEyeView view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene));
  const Rays a = view_rays(view, 300);
  // The dispatch covers all 300 rays (5 groups) but the count says 200: the
  // shader's bounds check leaves the rest as the layer filled them (NaN).
  DeviceBatch b(gpu(), a);
  static_cast<XrFoveatedDeviceRayCountFOVEART*>(b.count.data)->count = 200;
  ASSERT_TRUE(gpu().run([&](VkCommandBuffer cb) {
    barrier(cb, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
    b.batch.commandBuffer = cb;
    const bool ok = foveart_gpu_engine_trace_rays_device(g.get(), &b.batch) == XR_SUCCESS;
    barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
            VK_ACCESS_HOST_READ_BIT);
    return ok;
  }));
  const auto out = b.result();
  const auto ref = trace_cpu(*c, a);
  for (size_t i = 0; i < 200; ++i) EXPECT_NEAR(out[i].g, ref[i].g, 1e-3f * (ref[i].g + 1e-3f)) << i;
  for (size_t i = 200; i < 300; ++i) EXPECT_TRUE(std::isnan(out[i].r)) << i;
  EXPECT_EQ(g->counts().primary, 200u);
  // New buffers for every call (the layer's after a view size change), cached sets or not.
  for (size_t n : {size_t{100}, size_t{300}, size_t{100}}) {
    const Rays r = view_rays(view, n);
    expect_agreement(compare(trace_gpu(*g, r), trace_cpu(*c, r)), "room, buffers renewed");
  }
  EXPECT_EQ(g->counts().primary, 700u);
  expect_no_validation_errors();
}

// Frames in flight (the header's Lifetime clause): a set a recorded frame uses
// stays valid while more distinct buffers than the engine caches sets for
// (32) come in the same frame. Resetting the full pool would free the first
// batch's set inside the pending command buffer, which validation reports at
// submission; the engine retires the pool instead.
TEST(GpuTracer, ManyBuffersInOneFrameKeepTheFirstBatchsSetValid) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_lit_room();
  auto g = make_gpu(scene);
  auto c = make_cpu(scene);
  ASSERT_TRUE(g && c);
  const FoveartEyeView view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene));
  const Rays first_rays = view_rays(view, 64), other_rays = view_rays(view, 8);
  DeviceBatch first(gpu(), first_rays);
  std::vector<std::unique_ptr<DeviceBatch>> others;
  for (int i = 0; i < 40; ++i) others.push_back(std::make_unique<DeviceBatch>(gpu(), other_rays));
  ASSERT_TRUE(gpu().run([&](VkCommandBuffer cb) {
    auto trace_in_frame_7 = [&](DeviceBatch& b) {
      layer_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
      b.batch.commandBuffer = cb;
      b.batch.frameIndex = 7;
      return foveart_gpu_engine_trace_rays_device(g.get(), &b.batch) == XR_SUCCESS;
    };
    bool ok = trace_in_frame_7(first);
    for (auto& b : others) ok = trace_in_frame_7(*b) && ok;
    layer_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT);
    return ok;
  }));
  expect_agreement(compare(first.result(), trace_cpu(*c, first_rays)), "room, the first batch of 41");
  expect_agreement(compare(others.back()->result(), trace_cpu(*c, other_rays)), "room, the last batch of 41");
  expect_no_validation_errors();
}

// ---- the full render -----------------------------------------------------------------

TEST(GpuTracer, FullRenderMatchesRenderFullPerPixel) {
  REQUIRE_GPU();
  const Scene scene = foveart::engine::make_default_scene();
  FoveartEyeView view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene));
  view.width_px = 160;  // the FOVE frustum at a small size
  view.height_px = 180;
  constexpr uint32_t kSpp = 2;
  constexpr uint64_t kSeed = 0x1234567890ull;
  auto g = make_gpu(scene);
  auto c = make_cpu(scene);
  ASSERT_TRUE(g && c);

  foveart::foveation::ImageRgb image(1, 1);
  std::vector<float> depth;
  foveart::engine::RenderSettings settings;
  settings.spp = kSpp;
  settings.seed = kSeed;
  settings.out_depth_m = &depth;
  foveart::foveation::Executor executor(2);
  ASSERT_EQ(foveart::engine::render_full(foveart_engine_trace_rays, c.get(), view, settings, &image, executor).status,
            FOVEART_RESULT_SUCCESS);

  const size_t pixels = size_t{view.width_px} * view.height_px;
  HostBuffer out(gpu(), 16 * pixels);
  std::string error;
  ASSERT_TRUE(gpu().run([&](VkCommandBuffer cb) {
    const bool ok = g->record_full(cb, view, kSpp, kSeed, out.buffer, 0, &error);
    barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
            VK_ACCESS_HOST_READ_BIT);
    return ok;
  })) << error;
  std::vector<glm::vec4> gpu_px(pixels), cpu_px(pixels);
  std::memcpy(gpu_px.data(), out.data, 16 * pixels);
  for (size_t i = 0; i < pixels; ++i) {
    const float* p = image.rgb.data() + 3 * i;
    cpu_px[i] = glm::vec4(p[0], p[1], p[2], depth[i]);
  }
  // Pixel 0's jitter does not depend on the pixel term of the hash: pixel 0
  // agreeing and the rest not points at jitter.glsl's pixel * 0x100000001B3.
  const Agreement first = compare({gpu_px.begin(), gpu_px.begin() + 1}, {cpu_px.begin(), cpu_px.begin() + 1});
  SCOPED_TRACE(std::string("pixel 0 ") + (first.depth_off == 0 ? "agrees" : "differs"));
  expect_agreement(compare(gpu_px, cpu_px), "full render 160x180, 2 spp");
  EXPECT_EQ(g->counts().primary, kSpp * pixels);
  EXPECT_EQ(g->counts().primary, c->counts().primary);
  expect_no_validation_errors();
}

// ---- bad input ------------------------------------------------------------------------

TEST(GpuTracer, BadBatchesFailWithoutRecording) {
  REQUIRE_GPU();
  auto g = make_gpu(foveart::engine::make_lit_room());
  ASSERT_TRUE(g);
  Rays r;
  r.origin.assign(64, glm::vec3(0.0f));
  r.dir.assign(64, glm::vec3(0.0f, 0.0f, -1.0f));
  DeviceBatch b(gpu(), r);
  EXPECT_TRUE(gpu().run([&](VkCommandBuffer cb) {
    XrFoveatedDeviceRayBatchFOVEART bad = b.batch;
    bad.commandBuffer = cb;
    EXPECT_EQ(foveart_gpu_engine_trace_rays_device(nullptr, &bad), XR_ERROR_VALIDATION_FAILURE);
    EXPECT_EQ(foveart_gpu_engine_trace_rays_device(g.get(), nullptr), XR_ERROR_VALIDATION_FAILURE);
    bad.type = XR_TYPE_UNKNOWN;
    EXPECT_EQ(foveart_gpu_engine_trace_rays_device(g.get(), &bad), XR_ERROR_VALIDATION_FAILURE);
    bad = b.batch;
    bad.commandBuffer = cb;
    bad.rays.buffer = VK_NULL_HANDLE;
    EXPECT_EQ(foveart_gpu_engine_trace_rays_device(g.get(), &bad), XR_ERROR_VALIDATION_FAILURE);
    bad = b.batch;
    bad.commandBuffer = VK_NULL_HANDLE;
    EXPECT_EQ(foveart_gpu_engine_trace_rays_device(g.get(), &bad), XR_ERROR_VALIDATION_FAILURE);
    bad = b.batch;
    bad.commandBuffer = cb;
    bad.colors.offset = 4;  // not a multiple of minStorageBufferOffsetAlignment
    std::string error;
    EXPECT_FALSE(g->record_trace(bad, &error));
    EXPECT_NE(error.find("offset"), std::string::npos) << error;
    bad = b.batch;
    bad.commandBuffer = cb;
    bad.rayCount.size = 4;  // too small for the indirect command
    EXPECT_EQ(foveart_gpu_engine_trace_rays_device(g.get(), &bad), XR_ERROR_RUNTIME_FAILURE);
    FoveartEyeView view{};
    EXPECT_FALSE(g->record_full(cb, view, 1, 0, b.colors.buffer, 0, &error));  // not an eye view
    return true;
  }));
  EXPECT_EQ(g->counts().total(), 0u);  // nothing was recorded
  expect_no_validation_errors();
}

TEST(GpuTracer, BadScenesAndOptionsFailToCreate) {
  REQUIRE_GPU();
  std::string error;
  GpuTracerOptions deep;
  deep.max_depth = 99;
  EXPECT_EQ(GpuTracer::create(gpu().context(), Scene{}, deep, &error), nullptr);
  EXPECT_NE(error.find("max_depth"), std::string::npos) << error;
  Scene broken;
  broken.source = "broken";
  broken.mesh.positions.push_back({0, 0, 0});
  broken.mesh.normals.push_back({0, 1, 0});
  broken.mesh.triangles.push_back({0, 1, 2});
  broken.mesh.triangle_material.push_back(0);
  broken.materials.emplace_back();
  error.clear();
  EXPECT_EQ(GpuTracer::create(gpu().context(), broken, {}, &error), nullptr);
  EXPECT_NE(error.find("broken"), std::string::npos) << error;
  error.clear();
  EXPECT_EQ(GpuTracer::create(GpuContext{}, Scene{}, {}, &error), nullptr);
  EXPECT_FALSE(error.empty());
}

TEST(GpuTracer, EmptySceneSeesOnlySky) {
  REQUIRE_GPU();
  Scene s;
  s.source = "empty";
  auto g = make_gpu(s);
  ASSERT_TRUE(g);
  Rays r;
  r.origin = {glm::vec3(0.0f), glm::vec3(0.0f)};
  r.dir = {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f)};  // the second is invalid: black, no depth
  const auto out = trace_gpu(*g, r);
  EXPECT_NEAR(out[0].b, Scene{}.sky_zenith.z, 1e-6f);
  EXPECT_TRUE(std::isinf(out[0].w) && out[0].w > 0.0f);
  EXPECT_EQ(out[1].r + out[1].g + out[1].b, 0.0f);
  EXPECT_TRUE(std::isnan(out[1].w));
  expect_no_validation_errors();
}

}  // namespace
