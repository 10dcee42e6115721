// GpuTracer's backend choice and its VK_KHR_ray_tracing_pipeline backend.
// Everywhere (lavapipe has no ray-tracing extensions): automatic picks compute
// and says so; an explicit ray_tracing_pipeline request fails create() with an
// error naming the missing extension; the backend's BLAS primitive order and
// binding-table layout (pure arithmetic). Only where a device offers
// VK_KHR_ray_tracing_pipeline (skipped elsewhere, saying they need hardware
// ray tracing): the ray-tracing pipeline against the compute tracer on the
// same device and the same rays (the scenes of gpu_tracer_test.cpp, its
// per-ray tolerance, at most 0.1 % of rays flipped), per-kind ray counts, the
// full render per pixel, under synchronization validation.
#include <gpu_engine/gpu_tracer.hpp>
#include <gpu_engine/rt_device.hpp>

#include <engine/default_scene.hpp>
#include <engine/gltf_loader.hpp>
#include <engine/procedural_scenes.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/eye_rays.hpp>

#include "gpu_trace_fixtures.hpp"
#include "rt_layout.hpp"  // samples/gpu_engine/src: the backend's layout arithmetic

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
using foveart::gpu_engine::GpuBackend;
using foveart::gpu_engine::GpuContext;
using foveart::gpu_engine::GpuTracer;
using foveart::gpu_engine::GpuTracerOptions;
using foveart::gpu_engine::RayTracingDeviceSupport;
using foveart::layer::DevicePreference;
using namespace foveart::gpu_engine::testing;

// The CPU implementation every machine has (lavapipe), without ray-tracing extensions.
TestGpu& cpu_device() {
  static TestGpu g(DevicePreference::cpu, false);
  return g;
}

// A hardware GPU where there is one, with the ray-tracing extensions where offered.
TestGpu& rt_device() {
  static TestGpu g(DevicePreference::hardware_gpu, true);
  return g;
}

#define REQUIRE_DEVICE(gpu)                                   \
  do {                                                        \
    if (!(gpu).vk.ok()) GTEST_SKIP() << "no Vulkan device";   \
  } while (0)

#define REQUIRE_RAY_TRACING()                                                                                   \
  do {                                                                                                          \
    if (!rt_device().vk.ok()) GTEST_SKIP() << "needs a GPU with hardware ray tracing; no Vulkan device at all"; \
    if (!rt_device().ray_tracing)                                                                               \
      GTEST_SKIP() << "needs a GPU with hardware ray tracing (VK_KHR_ray_tracing_pipeline): "                   \
                   << rt_device().vk.name() << " lacks "                                                        \
                   << (rt_device().support ? rt_device().support->missing() : std::string("?"));               \
  } while (0)

std::unique_ptr<GpuTracer> make(TestGpu& gpu, Scene scene, GpuBackend backend, Effects allowed = Effects::all()) {
  std::string error;
  GpuTracerOptions options;
  options.backend = backend;
  options.allowed = allowed;
  auto t = GpuTracer::create(gpu.context(), std::move(scene), options, &error);
  EXPECT_NE(t, nullptr) << error;
  if (t) {
    EXPECT_EQ(t->backend(), backend);
  }
  return t;
}

// Both backends on the ray-tracing device.
struct Pair {
  std::unique_ptr<GpuTracer> rt, compute;
  Pair(const Scene& scene, Effects allowed = Effects::all())
      : rt(make(rt_device(), scene, GpuBackend::ray_tracing_pipeline, allowed)),
        compute(make(rt_device(), scene, GpuBackend::compute, allowed)) {}
  bool ok() const { return rt && compute; }
};

// The ray-tracing pipeline's traversal against the compute kernel's BVH: rays
// grazing an edge may see another surface, at most 0.1 % of them (the rest
// within kRayTolerance, ray_agreement.hpp). Not measured: no machine this
// project runs on offers VK_KHR_ray_tracing_pipeline.
constexpr double kRtFlippedShare = 0.001;

void expect_rt_agreement(const Agreement& a, const char* what) { expect_agreement(a, what, kRtFlippedShare); }

void expect_scene_agrees(const Scene& scene, const char* what, size_t n = 4096) {
  Pair p(scene);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.rt->effects(), p.compute->effects());
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), n);
  expect_rt_agreement(compare(trace(rt_device(), *p.rt, rays), trace(rt_device(), *p.compute, rays)), what);
  expect_no_validation_errors(rt_device());
}

Scene plain_floor() {  // one rough, opaque, untextured floor; no lights
  Scene s;
  s.source = "plain";
  foveart::engine::Material m;
  m.roughness = 1.0f;
  m.metallic = 0.0f;
  s.materials.push_back(m);
  add_floor(s, 2.0f, 0);
  return s;
}

void print_counts(const char* what, const RayCounts& c) {
  std::printf("[ counts ] %s: primary %llu shadow %llu reflection %llu refraction %llu\n", what,
              static_cast<unsigned long long>(c.primary), static_cast<unsigned long long>(c.shadow),
              static_cast<unsigned long long>(c.reflection), static_cast<unsigned long long>(c.refraction));
}

// ---- the choice, everywhere ------------------------------------------------------------

TEST(GpuTracerBackend, NamesEachBackend) {
  EXPECT_STREQ(foveart::gpu_engine::backend_name(GpuBackend::automatic), "automatic");
  EXPECT_STREQ(foveart::gpu_engine::backend_name(GpuBackend::compute), "compute");
  EXPECT_STREQ(foveart::gpu_engine::backend_name(GpuBackend::ray_tracing_pipeline), "ray_tracing_pipeline");
  EXPECT_EQ(GpuTracerOptions{}.backend, GpuBackend::automatic);
  EXPECT_FALSE(GpuContext{}.ray_tracing_enabled);
}

TEST(GpuTracerBackend, AutomaticPicksComputeOnADeviceWithoutRayTracing) {
  TestGpu& gpu = cpu_device();
  REQUIRE_DEVICE(gpu);
  const RayTracingDeviceSupport support(gpu.vk.device().physical_device);
  std::printf("[ device ] %s: VK_KHR_ray_tracing_pipeline backend %s%s\n", gpu.vk.name().c_str(),
              support.offered() ? "offered" : "not offered, lacks ", support.missing().c_str());
  // The device was created without the extensions: automatic is compute.
  std::string error;
  auto automatic = GpuTracer::create(gpu.context(), plain_floor(), {}, &error);
  ASSERT_NE(automatic, nullptr) << error;
  EXPECT_EQ(automatic->backend(), GpuBackend::compute);
  EXPECT_STREQ(automatic->backend_name(), "compute");
  // Saying the extensions are enabled on a device that does not offer them changes nothing.
  if (!support.offered()) {
    GpuContext claimed = gpu.context();
    claimed.ray_tracing_enabled = true;
    auto c = GpuTracer::create(claimed, plain_floor(), {}, &error);
    ASSERT_NE(c, nullptr) << error;
    EXPECT_EQ(c->backend(), GpuBackend::compute);
  }
  // And it traces: every ray counted, the floor's depth.
  const Rays rays = down_rays(8, 1.5f);
  const auto out = trace(gpu, *automatic, rays);
  EXPECT_EQ(automatic->counts().primary, rays.origin.size());
  for (const glm::vec4& v : out)
    EXPECT_NEAR(v.w, 1.0f / std::fabs(glm::normalize(glm::vec3(0.1f, -1.0f, 0.05f)).y), 1e-4f);
  expect_no_validation_errors(gpu);
}

TEST(GpuTracerBackend, RayTracingPipelineRequestFailsWhereTheDeviceLacksIt) {
  TestGpu& gpu = cpu_device();
  REQUIRE_DEVICE(gpu);
  const RayTracingDeviceSupport support(gpu.vk.device().physical_device);
  if (support.offered()) GTEST_SKIP() << gpu.vk.name() << " offers VK_KHR_ray_tracing_pipeline";
  EXPECT_FALSE(support.missing().empty());
  GpuTracerOptions options;
  options.backend = GpuBackend::ray_tracing_pipeline;
  for (bool claimed : {false, true}) {
    GpuContext context = gpu.context();
    context.ray_tracing_enabled = claimed;
    std::string error;
    EXPECT_EQ(GpuTracer::create(context, foveart::engine::make_default_scene(), options, &error), nullptr);
    EXPECT_NE(error.find(support.missing()), std::string::npos) << error;
    EXPECT_NE(error.find("ray_tracing_pipeline"), std::string::npos) << error;
    std::printf("[ error ] %s\n", error.c_str());
  }
  // Nothing to enable: the create info is left as it was.
  RayTracingDeviceSupport again(gpu.vk.device().physical_device);
  VkDeviceCreateInfo info{};
  std::vector<const char*> extensions;
  EXPECT_FALSE(again.enable(&info, &extensions));
  EXPECT_EQ(info.pNext, nullptr);
  EXPECT_TRUE(extensions.empty());
  // The device still serves the compute backend afterwards.
  auto t = make(gpu, plain_floor(), GpuBackend::compute);
  ASSERT_NE(t, nullptr);
  expect_no_validation_errors(gpu);
}

// A device that offers the extensions but was created without them. (It took
// lavapipe, which never offers them, so it skipped on every machine.)
TEST(GpuTracerBackend, RayTracingPipelineRequestFailsWhereTheCallerDidNotEnableIt) {
  static TestGpu gpu(DevicePreference::hardware_gpu, false);  // the extensions left off even where offered
  REQUIRE_DEVICE(gpu);
  const RayTracingDeviceSupport support(gpu.vk.device().physical_device);
  if (!support.offered())
    GTEST_SKIP() << "needs a GPU with hardware ray tracing (VK_KHR_ray_tracing_pipeline): " << gpu.vk.name()
                 << " lacks " << support.missing() << " (the test above covers a device without it)";
  GpuTracerOptions options;
  options.backend = GpuBackend::ray_tracing_pipeline;
  std::string error;
  EXPECT_EQ(GpuTracer::create(gpu.context(), plain_floor(), options, &error), nullptr);  // created without them
  EXPECT_NE(error.find(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME), std::string::npos) << error;
  EXPECT_NE(error.find("ray_tracing_enabled"), std::string::npos) << error;
}

// ---- the backend's layout arithmetic, everywhere ----------------------------------------

// The feature chain enable() builds is valid beside the caller's own: a Vulkan 1.2 caller's
// VkPhysicalDeviceVulkan12Features carries bufferDeviceAddress (no second struct for it, which
// the spec forbids in one chain); without one, the separate struct is chained.
TEST(GpuTracerRtDevice, FeatureChainSetsBufferDeviceAddressInTheCallersVulkan12Features) {
  for (const bool vulkan12 : {true, false}) {
    VkPhysicalDeviceVulkan12Features v12{};
    v12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    v12.timelineSemaphore = VK_TRUE;
    VkDeviceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    info.pNext = vulkan12 ? &v12 : nullptr;
    VkPhysicalDeviceBufferDeviceAddressFeaturesKHR address{};
    address.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES_KHR;
    address.bufferDeviceAddress = VK_TRUE;
    VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration{};
    acceleration.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
    VkPhysicalDeviceRayTracingPipelineFeaturesKHR pipeline{};
    pipeline.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR;
    RayTracingDeviceSupport::chain_features(&info, &address, &acceleration, &pipeline);
    std::vector<VkStructureType> chain;
    for (auto* s = static_cast<const VkBaseInStructure*>(info.pNext); s != nullptr; s = s->pNext) chain.push_back(s->sType);
    const std::vector<VkStructureType> expected =
        vulkan12 ? std::vector<VkStructureType>{pipeline.sType, acceleration.sType, v12.sType}
                 : std::vector<VkStructureType>{pipeline.sType, acceleration.sType, address.sType};
    EXPECT_EQ(chain, expected) << (vulkan12 ? "with" : "without") << " Vulkan12Features";
    EXPECT_EQ(v12.bufferDeviceAddress, vulkan12 ? VK_TRUE : VK_FALSE);
    EXPECT_EQ(v12.timelineSemaphore, VK_TRUE) << "the caller's other features stay";
  }
}

TEST(GpuTracerRtLayout, EachTracedTriangleOnceOpaqueFirst) {
  using foveart::gpu_engine::GpuTriangle;
  std::vector<GpuTriangle> tris(5);
  const uint32_t masked[5] = {0, 1, 0, 1, 0};
  for (size_t i = 0; i < tris.size(); ++i) tris[i].masked = masked[i];
  // Triangle 2 is not in the BVH (a MASK material cut out whole); 1 and 4 sit in two leaves.
  auto order = foveart::gpu_engine::order_rt_primitives({4, 1, 1, 0, 3, 4}, tris);
  EXPECT_EQ(order.prims, (std::vector<uint32_t>{0, 4, 1, 3}));
  EXPECT_EQ(order.geometry1_first, 2u);
  for (GpuTriangle& t : tris) t.masked = 0;
  order = foveart::gpu_engine::order_rt_primitives({2, 0}, tris);
  EXPECT_EQ(order.prims, (std::vector<uint32_t>{0, 2}));
  EXPECT_EQ(order.geometry1_first, 2u);  // no masked geometry
  for (GpuTriangle& t : tris) t.masked = 1;
  order = foveart::gpu_engine::order_rt_primitives({3, 1}, tris);
  EXPECT_EQ(order.prims, (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(order.geometry1_first, 0u);  // the masked geometry is geometry 0: no offset
  order = foveart::gpu_engine::order_rt_primitives({}, {});
  EXPECT_TRUE(order.prims.empty());
  EXPECT_EQ(order.geometry1_first, 0u);
}

TEST(GpuTracerRtLayout, BindingTableRegionsRespectTheDeviceAlignments) {
  using foveart::gpu_engine::binding_table_layout;
  auto l = binding_table_layout(32, 32, 64);  // common desktop values
  EXPECT_EQ(l.record_stride_bytes, 32u);
  EXPECT_EQ(l.raygen_offset_bytes, 0u);
  EXPECT_EQ(l.miss_offset_bytes, 64u);
  EXPECT_EQ(l.hit_offset_bytes, 128u);
  EXPECT_EQ(l.table_bytes, 160u);
  l = binding_table_layout(48, 16, 64);  // a handle that is not a power of two
  EXPECT_EQ(l.record_stride_bytes, 48u);
  EXPECT_EQ(l.miss_offset_bytes, 64u);
  EXPECT_EQ(l.hit_offset_bytes, 192u);  // 64 + 2 x 48 = 160, up to 192
  EXPECT_EQ(l.table_bytes, 240u);
  for (uint32_t handle : {16u, 32u, 48u, 64u})
    for (uint32_t align : {1u, 16u, 32u, 64u})
      for (uint32_t base : {1u, 64u, 256u}) {
        l = binding_table_layout(handle, align, base);
        SCOPED_TRACE(std::to_string(handle) + " " + std::to_string(align) + " " + std::to_string(base));
        EXPECT_GE(l.record_stride_bytes, handle);
        EXPECT_EQ(l.record_stride_bytes % align, 0u);
        EXPECT_EQ(l.miss_offset_bytes % base, 0u);
        EXPECT_EQ(l.hit_offset_bytes % base, 0u);
        EXPECT_GE(l.miss_offset_bytes, l.raygen_offset_bytes + l.record_stride_bytes);
        EXPECT_GE(l.hit_offset_bytes, l.miss_offset_bytes + 2 * l.record_stride_bytes);
        EXPECT_EQ(l.table_bytes, l.hit_offset_bytes + l.record_stride_bytes);
      }
}

// ---- the ray-tracing pipeline against the compute tracer, where a device offers it ------

TEST(GpuTracerRt, AutomaticPicksTheRayTracingPipelineWhereEnabled) {
  REQUIRE_RAY_TRACING();
  std::string error;
  auto t = GpuTracer::create(rt_device().context(), plain_floor(), {}, &error);
  ASSERT_NE(t, nullptr) << error;
  EXPECT_EQ(t->backend(), GpuBackend::ray_tracing_pipeline);
  EXPECT_STREQ(t->backend_name(), "ray_tracing_pipeline");
}

TEST(GpuTracerRt, DefaultSceneAgreesWithTheComputeTracerPerRay) {
  REQUIRE_RAY_TRACING();
  const Scene scene = foveart::engine::make_default_scene();
  const Effects fx = foveart::engine::derive_effects(scene);
  ASSERT_TRUE(fx.shadows && fx.reflection && fx.refraction && fx.textures);
  expect_scene_agrees(scene, "rt vs compute: default scene");
}

TEST(GpuTracerRt, LitRoomAgreesWithTheComputeTracerPerRay) {
  REQUIRE_RAY_TRACING();
  expect_scene_agrees(foveart::engine::make_lit_room(), "rt vs compute: room (12 point lights)");
}

TEST(GpuTracerRt, TexturedHallAgreesWithTheComputeTracerPerRay) {
  REQUIRE_RAY_TRACING();
  expect_scene_agrees(foveart::engine::make_textured_hall(), "rt vs compute: hall (textures, spot lights)");
}

TEST(GpuTracerRt, TexturedGltfAgreesWithTheComputeTracerPerRay) {
  REQUIRE_RAY_TRACING();
  const std::filesystem::path file = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not installed (assimp-testmodels)";
  const foveart::engine::LoadResult loaded = foveart::engine::load_gltf(file.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  expect_scene_agrees(*loaded.scene, "rt vs compute: BoxTextured.gltf");
}

TEST(GpuTracerRt, AlphaMaskCutsOutTheSameTexelsAsTheComputeTracer) {
  REQUIRE_RAY_TRACING();
  Scene s;
  s.source = "mask";
  foveart::engine::Material m;
  m.roughness = 1.0f;
  m.metallic = 0.0f;
  m.alpha_mode = foveart::engine::AlphaMode::kMask;
  m.base_color_texture = 0;
  s.materials.push_back(m);
  foveart::engine::Material opaque;  // an opaque floor below: geometry 0 and 1 both present
  opaque.roughness = 1.0f;
  opaque.metallic = 0.0f;
  opaque.base_color = glm::vec4(0.2f, 0.3f, 0.9f, 1.0f);
  s.materials.push_back(opaque);
  foveart::engine::Texture t;  // left half transparent, right half opaque
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 1)};
  t.nearest = true;
  s.textures.push_back(t);
  add_floor(s, 1.0f, 0);
  const auto below = static_cast<uint32_t>(s.mesh.positions.size());
  add_floor(s, 3.0f, 1);
  for (uint32_t i = below; i < s.mesh.positions.size(); ++i) s.mesh.positions[i].y = -1.0f;
  Pair p(s);
  ASSERT_TRUE(p.ok());
  const Rays rays = down_rays(32, 0.9f);
  const auto rt = trace(rt_device(), *p.rt, rays);
  const auto compute = trace(rt_device(), *p.compute, rays);
  size_t through = 0;  // rays that pass the cut-out half and hit the floor below
  const float near_depth = 1.0f / std::fabs(glm::normalize(glm::vec3(0.1f, -1.0f, 0.05f)).y);
  for (const glm::vec4& v : rt) through += v.w > 1.5f * near_depth ? 1 : 0;
  EXPECT_GT(through, rays.origin.size() / 4);
  EXPECT_LT(through, 3 * rays.origin.size() / 4);
  expect_rt_agreement(compare(rt, compute), "rt vs compute: alpha mask over an opaque floor");
  // Shadow rays through the mask too: a light above, both floors lit.
  foveart::engine::Light light;
  light.position = glm::vec3(0.2f, 3.0f, 0.1f);
  light.intensity = 20.0f;
  s.lights.push_back(light);
  Pair lit(s);
  ASSERT_TRUE(lit.ok());
  const Rays wide = down_rays(32, 2.5f);
  expect_rt_agreement(compare(trace(rt_device(), *lit.rt, wide), trace(rt_device(), *lit.compute, wide)),
                   "rt vs compute: shadows through the alpha mask");
  EXPECT_EQ(lit.rt->counts().shadow, lit.compute->counts().shadow);
  EXPECT_GT(lit.rt->counts().shadow, 0u);
  expect_no_validation_errors(rt_device());
}

TEST(GpuTracerRt, RayCountsEqualTheComputeTracersOnTheDefaultScene) {
  REQUIRE_RAY_TRACING();
  const Scene scene = foveart::engine::make_default_scene();
  Pair p(scene);
  ASSERT_TRUE(p.ok());
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 4096);
  trace(rt_device(), *p.rt, rays);
  trace(rt_device(), *p.compute, rays);
  const RayCounts rc = p.rt->counts(), cc = p.compute->counts();
  print_counts("rt", rc);
  print_counts("compute", cc);
  EXPECT_EQ(rc.primary, 4096u);
  EXPECT_EQ(rc.primary, cc.primary);
  // As gpu_tracer_test.cpp: the few rays that graze an edge may flip (another
  // triangle test) and change the secondary counts by a hair.
  auto near = [](uint64_t a, uint64_t b) { return std::fabs(double(a) - double(b)) <= 0.005 * double(b) + 2.0; };
  EXPECT_GT(cc.shadow, 0u);
  EXPECT_GT(cc.reflection, 0u);
  EXPECT_GT(cc.refraction, 0u);
  EXPECT_TRUE(near(rc.shadow, cc.shadow));
  EXPECT_TRUE(near(rc.reflection, cc.reflection));
  EXPECT_TRUE(near(rc.refraction, cc.refraction));
  p.rt->reset_counts();
  EXPECT_EQ(p.rt->counts().total(), 0u);
  expect_no_validation_errors(rt_device());
}

TEST(GpuTracerRt, AbsentEffectsCastNoRays) {
  REQUIRE_RAY_TRACING();
  auto t = make(rt_device(), plain_floor(), GpuBackend::ray_tracing_pipeline);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->effects(), Effects::none());
  const Rays rays = down_rays(16, 1.5f);
  const auto out = trace(rt_device(), *t, rays);
  const RayCounts c = t->counts();
  EXPECT_EQ(c.primary, rays.origin.size());
  EXPECT_EQ(c.shadow, 0u);
  EXPECT_EQ(c.reflection, 0u);
  EXPECT_EQ(c.refraction, 0u);
  for (const glm::vec4& v : out)
    EXPECT_NEAR(v.w, 1.0f / std::fabs(glm::normalize(glm::vec3(0.1f, -1.0f, 0.05f)).y), 1e-4f);
  expect_no_validation_errors(rt_device());
}

TEST(GpuTracerRt, EffectsNotAllowedCastNoRaysAndMatchTheComputeKernel) {
  REQUIRE_RAY_TRACING();
  const Scene scene = foveart::engine::make_default_scene();
  Pair p(scene, Effects::none());
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.rt->effects(), Effects::none());
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 2048);
  expect_rt_agreement(compare(trace(rt_device(), *p.rt, rays), trace(rt_device(), *p.compute, rays)),
                   "rt vs compute: default scene, primary only");
  const RayCounts c = p.rt->counts();
  EXPECT_EQ(c.primary, 2048u);
  EXPECT_EQ(c.shadow + c.reflection + c.refraction, 0u);
  expect_no_validation_errors(rt_device());
}

TEST(GpuTracerRt, TracesOnlyTheCountedRays) {
  REQUIRE_RAY_TRACING();
  const Scene scene = foveart::engine::make_lit_room();
  Pair p(scene);
  ASSERT_TRUE(p.ok());
  const Rays a = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 300);
  // The launch covers the capacity (300) but the count says 200: the rest stay NaN.
  DeviceBatch b(rt_device(), a);
  static_cast<XrFoveatedDeviceRayCountFOVEART*>(b.count.data)->count = 200;
  ASSERT_TRUE(trace_batch(rt_device(), *p.rt, b));
  const auto out = b.result();
  const auto ref = trace(rt_device(), *p.compute, a);
  expect_rt_agreement(compare({out.begin(), out.begin() + 200}, {ref.begin(), ref.begin() + 200}),
                   "rt vs compute: room, 200 of 300");
  for (size_t i = 200; i < 300; ++i) EXPECT_TRUE(std::isnan(out[i].r)) << i;
  EXPECT_EQ(p.rt->counts().primary, 200u);
  expect_no_validation_errors(rt_device());
}

// With the count buffer's address chained (XrFoveatedDeviceRayAddressesFOVEART) the launch is
// vkCmdTraceRaysIndirectKHR of traceRays: set below the count, only those rays are traced.
TEST(GpuTracerRt, LaunchesIndirectlyFromTheTraceRaysArguments) {
  REQUIRE_RAY_TRACING();
  if (!rt_device().context().trace_rays_indirect)
    GTEST_SKIP() << rt_device().vk.name() << " lacks rayTracingPipelineTraceRaysIndirect";
  const Scene scene = foveart::engine::make_lit_room();
  Pair p(scene);
  ASSERT_TRUE(p.ok());
  const Rays a = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), 300);
  DeviceBatch b(rt_device(), a);
  HostBuffer count(rt_device(), sizeof(XrFoveatedDeviceRayCountFOVEART), true);
  ASSERT_NE(count.address, 0u);
  XrFoveatedDeviceRayCountFOVEART c{};
  c.count = 200;
  c.traceRays[0] = 50;  // two rows of 50: rays 0..99 of the 200 counted
  c.traceRays[1] = 2;
  c.traceRays[2] = 1;
  std::memcpy(count.data, &c, sizeof(c));
  b.batch.rayCount = {count.buffer, 0, sizeof(c)};
  XrFoveatedDeviceRayAddressesFOVEART addresses{};
  addresses.type = XR_TYPE_FOVEATED_DEVICE_RAY_ADDRESSES_FOVEART;
  addresses.rayCount = count.address;
  b.batch.next = &addresses;
  ASSERT_TRUE(trace_batch(rt_device(), *p.rt, b));
  const auto out = b.result();
  const auto ref = trace(rt_device(), *p.compute, a);
  expect_rt_agreement(compare({out.begin(), out.begin() + 100}, {ref.begin(), ref.begin() + 100}),
                      "rt indirect vs compute: room, 100 launched of 200 counted");
  for (size_t i = 100; i < 300; ++i) EXPECT_TRUE(std::isnan(out[i].r)) << i;
  EXPECT_EQ(p.rt->counts().primary, 100u);
  expect_no_validation_errors(rt_device());
}

TEST(GpuTracerRt, FullRenderMatchesTheComputeTracerPerPixel) {
  REQUIRE_RAY_TRACING();
  const Scene scene = foveart::engine::make_default_scene();
  FoveartEyeView view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene));
  view.width_px = 160;
  view.height_px = 180;
  constexpr uint32_t kSpp = 2;
  constexpr uint64_t kSeed = 0x1234567890ull;
  Pair p(scene);
  ASSERT_TRUE(p.ok());
  const size_t pixels = size_t{view.width_px} * view.height_px;
  auto render = [&](GpuTracer& t) {
    HostBuffer out(rt_device(), 16 * pixels);
    std::string error;
    EXPECT_TRUE(rt_device().run([&](VkCommandBuffer cb) {
      const bool ok = t.record_full(cb, view, kSpp, kSeed, out.buffer, 0, &error);
      layer_barrier(cb, VK_PIPELINE_STAGE_HOST_BIT);
      return ok;
    })) << error;
    std::vector<glm::vec4> px(pixels);
    std::memcpy(px.data(), out.data, 16 * pixels);
    return px;
  };
  expect_rt_agreement(compare(render(*p.rt), render(*p.compute)), "rt vs compute: full render 160x180, 2 spp");
  EXPECT_EQ(p.rt->counts().primary, kSpp * pixels);
  EXPECT_EQ(p.rt->counts().primary, p.compute->counts().primary);
  expect_no_validation_errors(rt_device());
}

TEST(GpuTracerRt, EmptySceneSeesOnlySky) {
  REQUIRE_RAY_TRACING();
  Scene s;
  s.source = "empty";
  auto t = make(rt_device(), s, GpuBackend::ray_tracing_pipeline);  // a TLAS without instances
  ASSERT_TRUE(t);
  Rays r;
  r.origin = {glm::vec3(0.0f), glm::vec3(0.0f)};
  r.dir = {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f)};  // the second is invalid: black, no depth
  const auto out = trace(rt_device(), *t, r);
  EXPECT_NEAR(out[0].b, Scene{}.sky_zenith.z, 1e-6f);
  EXPECT_TRUE(std::isinf(out[0].w) && out[0].w > 0.0f);
  EXPECT_EQ(out[1].r + out[1].g + out[1].b, 0.0f);
  EXPECT_TRUE(std::isnan(out[1].w));
  expect_no_validation_errors(rt_device());
}

}  // namespace
