#include "command_pool.hpp"

#include <stdexcept>
#include <string>

namespace foveart::hello {
namespace {

void check_pool(VkResult r, const char* call, const char* who) {
  if (r != VK_SUCCESS)
    throw std::runtime_error(std::string(call) + " (" + who + ") failed: VkResult " + std::to_string(r));
}

}  // namespace

void CommandPool::create(VkDevice device, std::uint32_t queue_family, std::size_t count, const char* who) {
  try {
    VkCommandPoolCreateInfo pool_info{};
    pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = queue_family;
    check_pool(vkCreateCommandPool(device, &pool_info, nullptr, &pool), "vkCreateCommandPool", who);
    VkCommandBufferAllocateInfo cb_info{};
    cb_info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    cb_info.commandPool = pool;
    cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cb_info.commandBufferCount = static_cast<std::uint32_t>(count);
    buffers.assign(count, VK_NULL_HANDLE);
    check_pool(vkAllocateCommandBuffers(device, &cb_info, buffers.data()), "vkAllocateCommandBuffers", who);
    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    fences.assign(count, VK_NULL_HANDLE);
    for (VkFence& fence : fences) check_pool(vkCreateFence(device, &fence_info, nullptr, &fence), "vkCreateFence", who);
  } catch (...) {
    destroy(device);
    throw;
  }
}

void CommandPool::destroy(VkDevice device) noexcept {
  for (VkFence fence : fences)
    if (fence != VK_NULL_HANDLE) vkDestroyFence(device, fence, nullptr);
  if (pool != VK_NULL_HANDLE) vkDestroyCommandPool(device, pool, nullptr);
  pool = VK_NULL_HANDLE;
  buffers.clear();
  fences.clear();
}

}  // namespace foveart::hello
