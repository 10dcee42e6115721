// GpuTracer's backend choice and its VK_KHR_ray_tracing_pipeline backend.
// Everywhere (lavapipe has no ray-tracing extensions): automatic picks compute
// and says so; an explicit ray_tracing_pipeline request fails create() with an
// error naming the missing extension; the backend's BLAS primitive order and
// binding-table layout (pure arithmetic). Only where a device offers
// VK_KHR_ray_tracing_pipeline (skipped elsewhere, with the reason): the
// ray-tracing pipeline against the compute tracer on the same device and the
// same rays (the scenes and tolerances of gpu_tracer_test.cpp), per-kind ray
// counts, the full render per pixel, under synchronization validation.
#include <gpu_engine/gpu_tracer.hpp>
#include <gpu_engine/rt_device.hpp>

#include <engine/default_scene.hpp>
#include <engine/gltf_loader.hpp>
#include <engine/procedural_scenes.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/eye_rays.hpp>

#include "headless_vulkan.hpp"
#include "icd_pin.h"
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
using foveart::layer::DeviceCreateHook;
using foveart::layer::DevicePreference;
using foveart::layer::HeadlessVulkan;

// A validated device, with the ray-tracing extensions enabled when asked for
// and offered, and a way to run commands on it.
struct Gpu {
  std::unique_ptr<RayTracingDeviceSupport> support;
  std::vector<const char*> extensions;
  bool ray_tracing = false;  // the device was created with the extensions
  HeadlessVulkan vk;
  VkQueue queue = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;

  Gpu(DevicePreference preference, bool enable_ray_tracing)
      : vk(preference, /*validate=*/true,
           enable_ray_tracing ? DeviceCreateHook([this](VkPhysicalDevice physical, VkDeviceCreateInfo* info) {
             support = std::make_unique<RayTracingDeviceSupport>(physical);
             ray_tracing = support->enable(info, &extensions);
           })
                              : DeviceCreateHook()) {
    foveart::sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
    if (!vk.ok()) return;
    std::printf("[ device ] %s, ray tracing %s, validation %s\n", vk.name().c_str(),
                ray_tracing ? "enabled" : "off", vk.validated() ? "on (synchronization)" : "off");
    vkGetDeviceQueue(vk.device().device, vk.device().queue_family_index, 0, &queue);
    VkCommandPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    info.queueFamilyIndex = vk.device().queue_family_index;
    vkCreateCommandPool(vk.device().device, &info, nullptr, &pool);
  }
  ~Gpu() {
    if (pool != VK_NULL_HANDLE) vkDestroyCommandPool(vk.device().device, pool, nullptr);
  }
  GpuContext context() const {
    GpuContext c{vk.device().physical_device, vk.device().device, vk.device().queue_family_index, queue};
    c.ray_tracing_enabled = ray_tracing;
    return c;
  }
  VkDevice device() const { return vk.device().device; }

  // Records with `record`, submits, waits. False when recording said so.
  bool run(const std::function<bool(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cb = VK_NULL_HANDLE;
    if (vkAllocateCommandBuffers(device(), &alloc, &cb) != VK_SUCCESS) return false;
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(cb, &begin);
    const bool ok = record(cb);
    vkEndCommandBuffer(cb);
    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VkFence fence = VK_NULL_HANDLE;
    vkCreateFence(device(), &fence_info, nullptr, &fence);
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cb;
    const bool submitted = vkQueueSubmit(queue, 1, &submit, fence) == VK_SUCCESS;
    if (submitted) vkWaitForFences(device(), 1, &fence, VK_TRUE, UINT64_MAX);
    vkDestroyFence(device(), fence, nullptr);
    vkFreeCommandBuffers(device(), pool, 1, &cb);
    return ok && submitted;
  }
  std::vector<std::string> errors() { return vk.errors(); }
};

// The CPU implementation every machine has (lavapipe), without ray-tracing extensions.
Gpu& cpu_device() {
  static Gpu g(DevicePreference::cpu, false);
  return g;
}

// A hardware GPU where there is one, with the ray-tracing extensions where offered.
Gpu& rt_device() {
  static Gpu g(DevicePreference::hardware_gpu, true);
  return g;
}

#define REQUIRE_DEVICE(gpu)                                   \
  do {                                                        \
    if (!(gpu).vk.ok()) GTEST_SKIP() << "no Vulkan device";   \
  } while (0)

#define REQUIRE_RAY_TRACING()                                                                                   \
  do {                                                                                                          \
    if (!rt_device().vk.ok()) GTEST_SKIP() << "no Vulkan device";                                               \
    if (!rt_device().ray_tracing)                                                                               \
      GTEST_SKIP() << "no Vulkan device offers VK_KHR_ray_tracing_pipeline (" << rt_device().vk.name()          \
                   << " lacks " << (rt_device().support ? rt_device().support->missing() : std::string("?"))   \
                   << ")";                                                                                      \
  } while (0)

// A host-visible buffer the layer would own (storage + indirect).
struct HostBuffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* data = nullptr;
  HostBuffer(Gpu& gpu, VkDeviceSize bytes) : device(gpu.device()) {
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    vkCreateBuffer(device, &info, nullptr, &buffer);
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(device, buffer, &req);
    VkPhysicalDeviceMemoryProperties props{};
    vkGetPhysicalDeviceMemoryProperties(gpu.vk.device().physical_device, &props);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = req.size;
    for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
      if ((req.memoryTypeBits & (1u << i)) && (props.memoryTypes[i].propertyFlags & want) == want) {
        alloc.memoryTypeIndex = i;
        break;
      }
    vkAllocateMemory(device, &alloc, nullptr, &memory);
    vkBindBufferMemory(device, buffer, memory, 0);
    vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &data);
  }
  ~HostBuffer() {
    vkDestroyBuffer(device, buffer, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
  HostBuffer(const HostBuffer&) = delete;
  HostBuffer& operator=(const HostBuffer&) = delete;
};

// The layer's barriers around the engine (XR_FOVEART_foveated_ray_tracing.h):
// full memory barriers, which cover the ray-tracing stage as the compute one.
void barrier(VkCommandBuffer cb, VkPipelineStageFlags dst) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT, dst, 0, 1, &b, 0,
                       nullptr, 0, nullptr);
}

struct Rays {
  std::vector<glm::vec3> origin, dir;
};

// n rays through pseudo-random screen positions of `view` (the LCG of gpu_tracer_test.cpp).
Rays view_rays(const FoveartEyeView& view, size_t n) {
  const foveart::foveation::EyeFrustum f = foveart::foveation::eye_frustum(view);
  const foveart::foveation::EyePose pose = foveart::foveation::eye_pose(view);
  Rays r;
  uint32_t state = 12345u;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / 16777216.0f;
  };
  for (size_t i = 0; i < n; ++i) {
    const glm::vec2 px(next() * static_cast<float>(view.width_px), next() * static_cast<float>(view.height_px));
    r.origin.push_back(pose.position_m);
    r.dir.push_back(foveart::foveation::eye_ray_direction(f, pose, px));
  }
  return r;
}

// A device ray batch as the layer hands it over (colours pre-filled with NaN).
struct DeviceBatch {
  HostBuffer count, rays, colors;
  XrFoveatedDeviceRayBatchFOVEART batch{};
  DeviceBatch(Gpu& gpu, const Rays& r)
      : count(gpu, sizeof(FoveartDeviceRayCount)), rays(gpu, 32 * std::max<size_t>(r.origin.size(), 1)),
        colors(gpu, 16 * std::max<size_t>(r.origin.size(), 1)) {
    const auto n = static_cast<uint32_t>(r.origin.size());
    FoveartDeviceRayCount c{};
    c.count = n;
    c.dispatch64[0] = (n + 63) / 64;
    c.dispatch64[1] = c.dispatch64[2] = 1;
    c.traceRays[0] = n;
    c.traceRays[1] = c.traceRays[2] = 1;
    std::memcpy(count.data, &c, sizeof(c));
    auto* ray = static_cast<float*>(rays.data);
    for (uint32_t i = 0; i < n; ++i) {
      const float e[8] = {r.origin[i].x, r.origin[i].y, r.origin[i].z, 0.0f, r.dir[i].x, r.dir[i].y, r.dir[i].z, 0.0f};
      std::memcpy(ray + 8 * i, e, sizeof(e));
    }
    auto* col = static_cast<float*>(colors.data);
    std::fill(col, col + 4 * std::max<uint32_t>(n, 1), std::numeric_limits<float>::quiet_NaN());
    batch.type = XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART;
    batch.rayCapacity = n;
    batch.raysPerPoint = 1;
    batch.rayCount = {count.buffer, 0, sizeof(FoveartDeviceRayCount)};
    batch.rays = {rays.buffer, 0, 32 * VkDeviceSize{std::max<uint32_t>(n, 1)}};
    batch.pointIndex = {rays.buffer, 0, 32};  // unused by the engine
    batch.colors = {colors.buffer, 0, 16 * VkDeviceSize{std::max<uint32_t>(n, 1)}};
  }
  std::vector<glm::vec4> result() const {
    std::vector<glm::vec4> out(batch.rayCapacity);
    std::memcpy(out.data(), colors.data, out.size() * sizeof(glm::vec4));
    return out;
  }
};

// Traces `batch` through the C entry point, the layer's barriers around it.
bool trace_batch(Gpu& gpu, GpuTracer& tracer, DeviceBatch& b) {
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  const bool ran = gpu.run([&](VkCommandBuffer cb) {
    barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
    b.batch.commandBuffer = cb;
    result = foveart_gpu_engine_trace_rays_device(&tracer, &b.batch);
    barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT);
    return result == XR_SUCCESS;
  });
  EXPECT_EQ(result, XR_SUCCESS);
  return ran;
}

std::vector<glm::vec4> trace(Gpu& gpu, GpuTracer& tracer, const Rays& r) {
  DeviceBatch b(gpu, r);
  EXPECT_TRUE(trace_batch(gpu, tracer, b));
  return b.result();
}

// gpu_tracer_test.cpp's agreement, the compute tracer as the reference: a ray's
// error is the largest channel difference relative to the reference's brightest
// channel (+1e-3 so black stays absolute).
struct Agreement {
  double within = 0.0;        // share of rays with error <= 1e-3
  double max_error = 0.0;
  double mean_error = 0.0;
  double depth_within = 0.0;  // share with the same hit/miss and |depth| within 1e-4 relative
  size_t n = 0;
};

Agreement compare(const std::vector<glm::vec4>& rt, const std::vector<glm::vec4>& ref) {
  Agreement a;
  a.n = ref.size();
  size_t ok = 0, depth_ok = 0;
  for (size_t i = 0; i < a.n; ++i) {
    const glm::vec4 g = rt[i], c = ref[i];
    const float diff = std::max({std::fabs(g.r - c.r), std::fabs(g.g - c.g), std::fabs(g.b - c.b)});
    const double err = std::isfinite(diff) ? double(diff) / (double(std::max({c.r, c.g, c.b})) + 1e-3) : 1e30;
    a.max_error = std::max(a.max_error, err);
    a.mean_error += err;
    if (err <= 1e-3) ++ok;
    if (std::isinf(c.w) ? std::isinf(g.w) && g.w > 0 : std::fabs(g.w - c.w) <= 1e-4f * std::max(1.0f, c.w)) ++depth_ok;
  }
  const double n = static_cast<double>(std::max<size_t>(a.n, 1));
  a.within = static_cast<double>(ok) / n;
  a.depth_within = static_cast<double>(depth_ok) / n;
  a.mean_error /= n;
  return a;
}

void expect_agreement(const Agreement& a, const char* what) {
  std::printf("[ agreement ] %s: %zu samples, %.4f%% within 1e-3, mean error %.2e, max error %.3g, depth %.4f%%\n",
              what, a.n, 100.0 * a.within, a.mean_error, a.max_error, 100.0 * a.depth_within);
  EXPECT_GE(a.within, 0.99) << what;
  EXPECT_LE(a.mean_error, 5e-3) << what;
  EXPECT_GE(a.depth_within, 0.995) << what;
}

void expect_no_validation_errors(Gpu& gpu) {
  const auto errors = gpu.errors();
  EXPECT_TRUE(errors.empty()) << (errors.empty() ? "" : errors.front());
}

std::unique_ptr<GpuTracer> make(Gpu& gpu, Scene scene, GpuBackend backend, Effects allowed = Effects::all()) {
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

void expect_scene_agrees(const Scene& scene, const char* what, size_t n = 4096) {
  Pair p(scene);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.rt->effects(), p.compute->effects());
  const Rays rays = view_rays(foveart::engine::fove_eye_view(0, foveart::engine::scene_head(scene)), n);
  expect_agreement(compare(trace(rt_device(), *p.rt, rays), trace(rt_device(), *p.compute, rays)), what);
  expect_no_validation_errors(rt_device());
}

// A (2 half) x (2 half) floor at y = 0, material `material`, uvs over [0,1]^2.
void add_floor(Scene& s, float half, uint32_t material) {
  const auto base = static_cast<uint32_t>(s.mesh.positions.size());
  const glm::vec3 p[4] = {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}};
  const glm::vec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    s.mesh.positions.push_back(p[i]);
    s.mesh.normals.push_back({0, 1, 0});
    s.mesh.uv0.push_back(uv[i]);
  }
  s.mesh.triangles.push_back({base, base + 2, base + 1});
  s.mesh.triangles.push_back({base, base + 3, base + 2});
  s.mesh.triangle_material.push_back(material);
  s.mesh.triangle_material.push_back(material);
}

Rays down_rays(int grid, float half) {
  Rays r;
  for (int i = 0; i < grid * grid; ++i) {
    const float x = -half + 2.0f * half * (static_cast<float>(i % grid) + 0.5f) / static_cast<float>(grid);
    const float z = -half + 2.0f * half * (static_cast<float>(i / grid) + 0.5f) / static_cast<float>(grid);
    r.origin.push_back({x, 1.0f, z});
    r.dir.push_back(glm::normalize(glm::vec3(0.1f, -1.0f, 0.05f)));
  }
  return r;
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
  Gpu& gpu = cpu_device();
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
  Gpu& gpu = cpu_device();
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

TEST(GpuTracerBackend, RayTracingPipelineRequestFailsWhereTheCallerDidNotEnableIt) {
  Gpu& gpu = cpu_device();
  REQUIRE_DEVICE(gpu);
  const RayTracingDeviceSupport support(gpu.vk.device().physical_device);
  if (!support.offered())
    GTEST_SKIP() << gpu.vk.name() << " does not offer the extensions (the test above covers it): lacks "
                 << support.missing();
  GpuTracerOptions options;
  options.backend = GpuBackend::ray_tracing_pipeline;
  std::string error;
  EXPECT_EQ(GpuTracer::create(gpu.context(), plain_floor(), options, &error), nullptr);  // created without them
  EXPECT_NE(error.find(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME), std::string::npos) << error;
  EXPECT_NE(error.find("ray_tracing_enabled"), std::string::npos) << error;
}

// ---- the backend's layout arithmetic, everywhere ----------------------------------------

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
  expect_agreement(compare(rt, compute), "rt vs compute: alpha mask over an opaque floor");
  // Shadow rays through the mask too: a light above, both floors lit.
  foveart::engine::Light light;
  light.position = glm::vec3(0.2f, 3.0f, 0.1f);
  light.intensity = 20.0f;
  s.lights.push_back(light);
  Pair lit(s);
  ASSERT_TRUE(lit.ok());
  const Rays wide = down_rays(32, 2.5f);
  expect_agreement(compare(trace(rt_device(), *lit.rt, wide), trace(rt_device(), *lit.compute, wide)),
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
  expect_agreement(compare(trace(rt_device(), *p.rt, rays), trace(rt_device(), *p.compute, rays)),
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
  static_cast<FoveartDeviceRayCount*>(b.count.data)->count = 200;
  ASSERT_TRUE(trace_batch(rt_device(), *p.rt, b));
  const auto out = b.result();
  const auto ref = trace(rt_device(), *p.compute, a);
  expect_agreement(compare({out.begin(), out.begin() + 200}, {ref.begin(), ref.begin() + 200}),
                   "rt vs compute: room, 200 of 300");
  for (size_t i = 200; i < 300; ++i) EXPECT_TRUE(std::isnan(out[i].r)) << i;
  EXPECT_EQ(p.rt->counts().primary, 200u);
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
      barrier(cb, VK_PIPELINE_STAGE_HOST_BIT);
      return ok;
    })) << error;
    std::vector<glm::vec4> px(pixels);
    std::memcpy(px.data(), out.data, 16 * pixels);
    return px;
  };
  expect_agreement(compare(render(*p.rt), render(*p.compute)), "rt vs compute: full render 160x180, 2 spp");
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
