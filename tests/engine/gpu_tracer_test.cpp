// GpuTracer against engine::Tracer: the same rays give the same radiance, depth
// and ray counts; the full render matches engine::render_full; bad input fails
// cleanly; synchronization validation stays silent. Runs on lavapipe.
#include <gpu_engine/gpu_tracer.hpp>

#include <engine/default_scene.hpp>
#include <engine/gltf_loader.hpp>
#include <engine/procedural_scenes.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/executor.hpp>
#include <foveation/eye_rays.hpp>

#include "headless_vulkan.hpp"
#include "icd_pin.h"

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
using foveart::layer::HeadlessVulkan;

// One validated lavapipe device for the whole suite, and a way to run commands on it.
struct Gpu {
  HeadlessVulkan vk{DevicePreference::cpu, /*validate=*/true};
  VkQueue queue = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;

  Gpu() {
    foveart::sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
    if (!vk.ok()) return;
    std::printf("[ device ] %s, validation %s\n", vk.name().c_str(), vk.validated() ? "on (synchronization)" : "off");
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
    return GpuContext{vk.device().physical_device, vk.device().device, vk.device().queue_family_index, queue};
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
};

Gpu& gpu() {
  static Gpu g;
  return g;
}

// A host-visible buffer the layer would own (storage + indirect).
struct HostBuffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* data = nullptr;
  HostBuffer(VkDeviceSize bytes) : device(gpu().device()) {
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    vkCreateBuffer(device, &info, nullptr, &buffer);
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(device, buffer, &req);
    VkPhysicalDeviceMemoryProperties props{};
    vkGetPhysicalDeviceMemoryProperties(gpu().vk.device().physical_device, &props);
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

// What the layer records around the engine's trace: host writes -> shader and
// indirect reads before, shader writes -> host reads after.
void barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
             VkAccessFlags dst_access) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

struct Rays {
  std::vector<glm::vec3> origin, dir;
};

// n rays through pseudo-random screen positions of `view` (a fixed LCG).
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

// A device ray batch as the layer hands it over.
struct DeviceBatch {
  HostBuffer count, rays, colors;
  XrFoveatedDeviceRayBatchFOVEART batch{};
  explicit DeviceBatch(const Rays& r)
      : count(sizeof(FoveartDeviceRayCount)), rays(32 * std::max<size_t>(r.origin.size(), 1)),
        colors(16 * std::max<size_t>(r.origin.size(), 1)) {
    const auto n = static_cast<uint32_t>(r.origin.size());
    FoveartDeviceRayCount c{};
    c.count = n;
    c.dispatch64[0] = (n + 63) / 64;
    c.dispatch64[1] = c.dispatch64[2] = 1;
    std::memcpy(count.data, &c, sizeof(c));
    auto* ray = static_cast<float*>(rays.data);
    for (uint32_t i = 0; i < n; ++i) {
      const float e[8] = {r.origin[i].x, r.origin[i].y, r.origin[i].z, 0.0f, r.dir[i].x, r.dir[i].y, r.dir[i].z, 0.0f};
      std::memcpy(ray + 8 * i, e, sizeof(e));
    }
    auto* col = static_cast<float*>(colors.data);
    std::fill(col, col + 4 * std::max<uint32_t>(n, 1), std::numeric_limits<float>::quiet_NaN());  // as the layer
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

// Traces through the C entry point, the layer's barriers around it.
std::vector<glm::vec4> trace_gpu(GpuTracer& tracer, const Rays& r) {
  DeviceBatch b(r);
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  EXPECT_TRUE(gpu().run([&](VkCommandBuffer cb) {
    barrier(cb, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
    b.batch.commandBuffer = cb;
    result = foveart_gpu_engine_trace_rays_device(&tracer, &b.batch);
    barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
            VK_ACCESS_HOST_READ_BIT);
    return result == XR_SUCCESS;
  }));
  EXPECT_EQ(result, XR_SUCCESS);
  return b.result();
}

// Agreement of two radiance/depth lists. A ray's error: the largest channel
// difference relative to the CPU's brightest channel (+1e-3 so black stays
// absolute). Float differences (traversal order, Embree's rcp, fma) flip a
// few rays that graze an edge, which then see another surface entirely.
struct Agreement {
  double within = 0.0;        // share of rays with error <= 1e-3
  double max_error = 0.0;     // over all rays
  double mean_error = 0.0;
  double depth_within = 0.0;  // share with the same hit/miss and |depth| within 1e-4 relative
  size_t n = 0;
};

Agreement compare(const std::vector<glm::vec4>& gpu_out, const std::vector<glm::vec4>& cpu_out) {
  Agreement a;
  a.n = cpu_out.size();
  size_t ok = 0, depth_ok = 0;
  for (size_t i = 0; i < a.n; ++i) {
    const glm::vec4 g = gpu_out[i], c = cpu_out[i];
    const float diff = std::max({std::fabs(g.r - c.r), std::fabs(g.g - c.g), std::fabs(g.b - c.b)});
    const double err = std::isfinite(diff) ? double(diff) / (double(std::max({c.r, c.g, c.b})) + 1e-3) : 1e30;
    a.max_error = std::max(a.max_error, err);
    a.mean_error += err;
    if (err <= 1e-3) ++ok;
    if (std::isinf(c.w) ? std::isinf(g.w) && g.w > 0 : std::fabs(g.w - c.w) <= 1e-4f * std::max(1.0f, c.w)) ++depth_ok;
  }
  a.within = static_cast<double>(ok) / static_cast<double>(std::max<size_t>(a.n, 1));
  a.depth_within = static_cast<double>(depth_ok) / static_cast<double>(std::max<size_t>(a.n, 1));
  a.mean_error /= static_cast<double>(std::max<size_t>(a.n, 1));
  return a;
}

void expect_agreement(const Agreement& a, const char* what) {
  std::printf("[ agreement ] %s: %zu samples, %.4f%% within 1e-3, mean error %.2e, max error %.3g, depth %.4f%%\n",
              what, a.n, 100.0 * a.within, a.mean_error, a.max_error, 100.0 * a.depth_within);
  EXPECT_GE(a.within, 0.99) << what;
  EXPECT_LE(a.mean_error, 5e-3) << what;
  EXPECT_GE(a.depth_within, 0.995) << what;
}

#define REQUIRE_GPU()                                                 \
  do {                                                                \
    if (!gpu().vk.ok()) GTEST_SKIP() << "no Vulkan device";           \
  } while (0)

void expect_no_validation_errors() {
  const auto errors = gpu().vk.errors();
  EXPECT_TRUE(errors.empty()) << (errors.empty() ? "" : errors.front());
}

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

// A rough floor of (2 half) x (2 half) at y = 0, material `material`, uvs over [0,1]^2.
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
  DeviceBatch b(a);
  static_cast<FoveartDeviceRayCount*>(b.count.data)->count = 200;
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
  HostBuffer out(16 * pixels);
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
  SCOPED_TRACE(std::string("pixel 0 ") + (first.depth_within == 1.0 ? "agrees" : "differs"));
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
  DeviceBatch b(r);
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
