#include "gpu/vk_util.hpp"

#include <vector>

namespace foveart::gpu {

bool create_bound_buffer(VkDevice device, const VkPhysicalDeviceMemoryProperties& memory_properties, VkDeviceSize size,
                         VkBufferUsageFlags usage, VkMemoryPropertyFlags wanted, VkBuffer* buffer,
                         VkDeviceMemory* memory, void** mapped, std::string* error,
                         std::span<const uint32_t> concurrent_families) {
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (concurrent_families.size() >= 2) {  // no ownership transfers between them
    info.sharingMode = VK_SHARING_MODE_CONCURRENT;
    info.queueFamilyIndexCount = uint32_t(concurrent_families.size());
    info.pQueueFamilyIndices = concurrent_families.data();
  }
  VkResult r = vkCreateBuffer(device, &info, nullptr, buffer);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateBuffer", r), false;
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(device, *buffer, &req);
  uint32_t type = UINT32_MAX;
  for (uint32_t i = 0; i < memory_properties.memoryTypeCount && type == UINT32_MAX; ++i) {
    if ((req.memoryTypeBits & (1u << i)) && (memory_properties.memoryTypes[i].propertyFlags & wanted) == wanted) type = i;
  }
  if (type == UINT32_MAX) {
    const bool host = (wanted & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
    return *error = std::string("no ") + (host ? "host-visible coherent" : "device-local") + " memory type", false;
  }
  auto alloc = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = type;
  auto flags = vk_struct<VkMemoryAllocateFlagsInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO);
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;  // a buffer with an address needs memory that has one
  if ((usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0) alloc.pNext = &flags;
  r = vkAllocateMemory(device, &alloc, nullptr, memory);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateMemory", r), false;
  r = vkBindBufferMemory(device, *buffer, *memory, 0);
  if (r != VK_SUCCESS) return *error = vk_error("vkBindBufferMemory", r), false;
  if (mapped != nullptr) {
    r = vkMapMemory(device, *memory, 0, VK_WHOLE_SIZE, 0, mapped);
    if (r != VK_SUCCESS) return *error = vk_error("vkMapMemory", r), false;
  }
  return true;
}

void destroy_buffer(VkDevice device, BoundBuffer* b) {
  if (b->mapped != nullptr) vkUnmapMemory(device, b->memory);
  if (b->buffer != VK_NULL_HANDLE) vkDestroyBuffer(device, b->buffer, nullptr);
  if (b->memory != VK_NULL_HANDLE) vkFreeMemory(device, b->memory, nullptr);
  *b = BoundBuffer{};
}

void memory_barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
                    VkAccessFlags dst_access) {
  auto b = vk_struct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

bool create_storage_pipeline_layout(VkDevice device, const uint32_t* descriptor_counts, uint32_t binding_count,
                                    uint32_t push_bytes, VkDescriptorSetLayout* set_layout,
                                    VkPipelineLayout* pipeline_layout, std::string* error) {
  std::vector<VkDescriptorSetLayoutBinding> bindings(binding_count);
  for (uint32_t b = 0; b < binding_count; ++b) {
    bindings[b].binding = b;
    bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[b].descriptorCount = descriptor_counts[b];
    bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set_info.bindingCount = binding_count;
  set_info.pBindings = bindings.data();
  VkResult r = vkCreateDescriptorSetLayout(device, &set_info, nullptr, set_layout);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateDescriptorSetLayout", r), false;
  const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  auto layout_info = vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = set_layout;
  layout_info.pushConstantRangeCount = 1;
  layout_info.pPushConstantRanges = &push;
  r = vkCreatePipelineLayout(device, &layout_info, nullptr, pipeline_layout);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreatePipelineLayout", r), false;
  return true;
}

void write_storage_descriptors(VkDevice device, VkDescriptorSet set, const VkDescriptorBufferInfo* buffers,
                               const uint32_t* descriptor_counts, uint32_t binding_count) {
  std::vector<VkWriteDescriptorSet> writes(binding_count);
  for (uint32_t b = 0; b < binding_count; ++b) {
    writes[b] = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[b].dstSet = set;
    writes[b].dstBinding = b;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].descriptorCount = descriptor_counts[b];
    writes[b].pBufferInfo = buffers;
    buffers += descriptor_counts[b];
  }
  vkUpdateDescriptorSets(device, binding_count, writes.data(), 0, nullptr);
}

bool allocate_storage_sets(VkDevice device, const VkDescriptorSetLayout* layouts, uint32_t set_count,
                           uint32_t storage_buffers, VkDescriptorPool* pool, VkDescriptorSet* sets, std::string* error) {
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, storage_buffers};
  auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = set_count;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  VkResult r = vkCreateDescriptorPool(device, &pool_info, nullptr, pool);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateDescriptorPool", r), false;
  auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = *pool;
  alloc.descriptorSetCount = set_count;
  alloc.pSetLayouts = layouts;
  r = vkAllocateDescriptorSets(device, &alloc, sets);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateDescriptorSets", r), false;
  return true;
}

bool create_compute_pipeline(VkDevice device, VkPipelineLayout layout, const uint32_t* code, size_t bytes,
                             VkPipeline* pipeline, std::string* error) {
  auto module_info = vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  module_info.codeSize = bytes;
  module_info.pCode = code;
  VkShaderModule module = VK_NULL_HANDLE;
  VkResult r = vkCreateShaderModule(device, &module_info, nullptr, &module);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateShaderModule", r), false;
  auto info = vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.layout = layout;
  r = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, pipeline);
  vkDestroyShaderModule(device, module, nullptr);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateComputePipelines", r), false;
  return true;
}

void record_copy_to_image(VkCommandBuffer cb, VkBuffer buffer, VkImage image, uint32_t width_px, uint32_t height_px) {
  auto to_transfer = vk_struct<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
  // After the image's last writes (an earlier frame's copy and layout change, the
  // runtime's read), which may still be in flight: they end at this stage.
  to_transfer.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  to_transfer.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_transfer.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;  // every texel is overwritten
  to_transfer.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  to_transfer.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_transfer.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_transfer.image = image;
  to_transfer.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &to_transfer);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {width_px, height_px, 1};
  vkCmdCopyBufferToImage(cb, buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  VkImageMemoryBarrier to_attachment = to_transfer;
  to_attachment.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_attachment.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  to_attachment.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  to_attachment.newLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &to_attachment);
}

}  // namespace foveart::gpu
