// Small helpers every device stage (and the layer's swapchain upload) shares:
// a zeroed struct with its sType set, the message for a failed call, buffers,
// barriers, storage-buffer pipelines and the copy into a swapchain image.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace foveart::gpu {

template <class T>
T vk_struct(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

// The compute passes' barriers: shader reads and writes, compute stage.
constexpr VkAccessFlags kShaderRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;

inline std::string vk_error(const char* what, VkResult r) {
  return std::string(what) + " failed (VkResult " + std::to_string(r) + ")";
}

// A buffer with its own memory, mapped when host-visible.
struct BoundBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  VkDeviceSize size = 0;
};
// Unmaps, destroys and frees what of *b exists, and empties it.
void destroy_buffer(VkDevice device, BoundBuffer* b);

// The memory a GPU-path buffer asks for: host-visible and coherent when the
// host writes or reads it every frame (it stays mapped), device-local otherwise.
inline VkMemoryPropertyFlags buffer_memory_flags(bool host_visible) {
  return host_visible
             ? VkMemoryPropertyFlags(VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)
             : VkMemoryPropertyFlags(VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
}

// A buffer of `size` bytes bound to new memory of the first type with all of
// `wanted` (and mapped into *mapped when mapped is not null); false with
// *error naming what failed. The caller destroys what was created either way.
// Two or more concurrent_families: VK_SHARING_MODE_CONCURRENT over them; else exclusive.
[[nodiscard]] bool create_bound_buffer(VkDevice device, const VkPhysicalDeviceMemoryProperties& memory_properties, VkDeviceSize size,
                         VkBufferUsageFlags usage, VkMemoryPropertyFlags wanted, VkBuffer* buffer,
                         VkDeviceMemory* memory, void** mapped, std::string* error,
                         std::span<const uint32_t> concurrent_families = {});

// One global memory barrier: the GPU frame's passes are whole-buffer
// producers and consumers, so a memory barrier says all there is.
void memory_barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
                    VkAccessFlags dst_access);

// The layout of compute pipelines that bind one set of storage buffers
// (binding b: descriptor_counts[b] buffers) and push `push_bytes` of constants; false with *error.
[[nodiscard]] bool create_storage_pipeline_layout(VkDevice device, const uint32_t* descriptor_counts, uint32_t binding_count,
                                    uint32_t push_bytes, VkDescriptorSetLayout* set_layout,
                                    VkPipelineLayout* pipeline_layout, std::string* error);

// Points binding b of `set` (storage buffers) at the next descriptor_counts[b] entries of `buffers`.
void write_storage_descriptors(VkDevice device, VkDescriptorSet set, const VkDescriptorBufferInfo* buffers,
                               const uint32_t* descriptor_counts, uint32_t binding_count);

// A descriptor pool of `set_count` sets holding `storage_buffers` storage-buffer
// descriptors in all, and one set of each layouts[i] from it into sets[i]; false with *error.
[[nodiscard]] bool allocate_storage_sets(VkDevice device, const VkDescriptorSetLayout* layouts, uint32_t set_count,
                                         uint32_t storage_buffers, VkDescriptorPool* pool, VkDescriptorSet* sets,
                                         std::string* error);

// A compute pipeline of SPIR-V `code` (`bytes` long, entry point "main") in `layout`; false with *error.
[[nodiscard]] bool create_compute_pipeline(VkDevice device, VkPipelineLayout layout, const uint32_t* code, size_t bytes,
                             VkPipeline* pipeline, std::string* error);

// Records the copy of tightly packed RGBA8 texels in `buffer` into `image`
// (any previous layout; every texel is overwritten), leaving it in
// COLOR_ATTACHMENT_OPTIMAL as OpenXR requires at release.
void record_copy_to_image(VkCommandBuffer cb, VkBuffer buffer, VkImage image, uint32_t width_px, uint32_t height_px);

}  // namespace foveart::gpu
