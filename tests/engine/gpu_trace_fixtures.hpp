// The GPU sample engine's test fixtures, shared by gpu_tracer_test.cpp (against
// engine::Tracer) and gpu_tracer_rt_test.cpp (the ray-tracing pipeline against
// the compute backend): a validated device and a way to run commands on it,
// host-visible buffers, ray sets, a device ray batch as the layer hands it over,
// the trace between the layer's barriers (the per-ray agreement measure:
// ray_agreement.hpp).
#pragma once

#include <gpu_engine/gpu_tracer.hpp>
#include <gpu_engine/rt_device.hpp>

#include <engine/scene.hpp>

#include <foveation/eye_rays.hpp>

#include "headless_vulkan.hpp"
#include "icd_pin.h"
#include "ray_agreement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace foveart::gpu_engine::testing {

using engine::Scene;
using layer::DeviceCreateHook;
using layer::DevicePreference;
using layer::HeadlessVulkan;

// A validated device, with the ray-tracing extensions enabled when asked for
// and offered, and a way to run commands on it.
struct TestGpu {
  std::unique_ptr<RayTracingDeviceSupport> support;
  std::vector<const char*> extensions;
  bool ray_tracing = false;  // the device was created with the extensions
  HeadlessVulkan vk;
  VkQueue queue = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;

  TestGpu(DevicePreference preference, bool enable_ray_tracing)
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
  ~TestGpu() {
    if (pool != VK_NULL_HANDLE) vkDestroyCommandPool(vk.device().device, pool, nullptr);
  }
  GpuContext context() const {
    GpuContext c{vk.device().physical_device, vk.device().device, vk.device().queue_family_index, queue};
    c.ray_tracing_enabled = ray_tracing;
    c.trace_rays_indirect = ray_tracing && support != nullptr && support->trace_rays_indirect();
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

// A host-visible buffer the layer would own (storage + indirect; + a device address when asked).
struct HostBuffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* data = nullptr;
  VkDeviceAddress address = 0;  // with_address only
  HostBuffer(TestGpu& gpu, VkDeviceSize bytes, bool with_address = false) : device(gpu.device()) {
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                 (with_address ? VkBufferUsageFlags{VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT} : VkBufferUsageFlags{0});
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
    VkMemoryAllocateFlagsInfo flags{};
    flags.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO;
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    if (with_address) alloc.pNext = &flags;
    vkAllocateMemory(device, &alloc, nullptr, &memory);
    vkBindBufferMemory(device, buffer, memory, 0);
    vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &data);
    if (with_address) {
      auto get = reinterpret_cast<PFN_vkGetBufferDeviceAddressKHR>(vkGetDeviceProcAddr(device, "vkGetBufferDeviceAddressKHR"));
      VkBufferDeviceAddressInfo address_info{};
      address_info.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO;
      address_info.buffer = buffer;
      if (get != nullptr) address = get(device, &address_info);
    }
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
inline void layer_barrier(VkCommandBuffer cb, VkPipelineStageFlags dst) {
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

// n rays through pseudo-random screen positions of `view` (a fixed LCG).
inline Rays view_rays(const FoveartEyeView& view, size_t n) {
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
  DeviceBatch(TestGpu& gpu, const Rays& r)
      : count(gpu, sizeof(XrFoveatedDeviceRayCountFOVEART)), rays(gpu, 32 * std::max<size_t>(r.origin.size(), 1)),
        colors(gpu, 16 * std::max<size_t>(r.origin.size(), 1)) {
    const auto n = static_cast<uint32_t>(r.origin.size());
    XrFoveatedDeviceRayCountFOVEART c{};
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
    batch.rayCount = {count.buffer, 0, sizeof(XrFoveatedDeviceRayCountFOVEART)};
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
inline bool trace_batch(TestGpu& gpu, GpuTracer& tracer, DeviceBatch& b) {
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  const bool ran = gpu.run([&](VkCommandBuffer cb) {
    layer_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
    b.batch.commandBuffer = cb;
    result = foveart_gpu_engine_trace_rays_device(&tracer, &b.batch);
    layer_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT);
    return result == XR_SUCCESS;
  });
  EXPECT_EQ(result, XR_SUCCESS);
  return ran;
}

inline std::vector<glm::vec4> trace(TestGpu& gpu, GpuTracer& tracer, const Rays& r) {
  DeviceBatch b(gpu, r);
  EXPECT_TRUE(trace_batch(gpu, tracer, b));
  return b.result();
}

// Validation heard the device (the layer is enabled and a messenger registered:
// vulkan-validationlayers is a dependency, scripts/setup.sh) and reported nothing.
inline void expect_no_validation_errors(TestGpu& gpu) {
  ASSERT_TRUE(gpu.vk.validated()) << "validation is not active on " << gpu.vk.name()
                                  << ": VK_LAYER_KHRONOS_validation missing (vulkan-validationlayers) or no messenger";
  const auto errors = gpu.errors();
  EXPECT_TRUE(errors.empty()) << errors.size() << " validation error(s), the first: "
                              << (errors.empty() ? "" : errors.front());
}

// A (2 half) x (2 half) floor at y = 0, material `material`, uvs over [0,1]^2.
inline void add_floor(Scene& s, float half, uint32_t material) {
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

inline Rays down_rays(int grid, float half) {
  Rays r;
  for (int i = 0; i < grid * grid; ++i) {
    const float x = -half + 2.0f * half * (static_cast<float>(i % grid) + 0.5f) / static_cast<float>(grid);
    const float z = -half + 2.0f * half * (static_cast<float>(i / grid) + 0.5f) / static_cast<float>(grid);
    r.origin.push_back({x, 1.0f, z});
    r.dir.push_back(glm::normalize(glm::vec3(0.1f, -1.0f, 0.05f)));
  }
  return r;
}

}  // namespace foveart::gpu_engine::testing
