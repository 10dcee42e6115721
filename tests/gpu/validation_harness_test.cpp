// The in-process validation the GPU suites rely on (tests/common/headless_vulkan.hpp)
// can fail: a hazard recorded on purpose (two fills of one buffer, no barrier
// between them) reaches errors() as a SYNC-HAZARD message, the same commands with
// the barrier stay silent, and messages from several threads all arrive. Without
// these, "validation stays silent" in the GPU suites would pass with a deaf harness.
#include "headless_vulkan.hpp"
#include "icd_pin.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace foveart::layer {
namespace {

// A device buffer, a command pool and a queue on a fresh validated lavapipe device.
class ValidationHarness : public ::testing::Test {
 protected:
  void SetUp() override {
    vk_ = std::make_unique<HeadlessVulkan>(DevicePreference::cpu, true);
    sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
    ASSERT_TRUE(vk_->ok()) << "no Vulkan device (mesa-vulkan-drivers brings lavapipe)";
    ASSERT_TRUE(vk_->validated()) << "validation not active: VK_LAYER_KHRONOS_validation missing "
                                     "(vulkan-validationlayers) or no debug messenger";
    device_ = vk_->device().device;
    vkGetDeviceQueue(device_, vk_->device().queue_family_index, 0, &queue_);
    VkCommandPoolCreateInfo pool{};
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = vk_->device().queue_family_index;
    ASSERT_EQ(vkCreateCommandPool(device_, &pool, nullptr, &pool_), VK_SUCCESS);
    ASSERT_TRUE(make_buffer(&buffer_, &memory_));
  }
  void TearDown() override {
    if (device_ == VK_NULL_HANDLE) return;
    vkDeviceWaitIdle(device_);
    vkDestroyBuffer(device_, buffer_, nullptr);
    vkFreeMemory(device_, memory_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
  }

  bool make_buffer(VkBuffer* buffer, VkDeviceMemory* memory) const {
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = kBytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if (vkCreateBuffer(device_, &info, nullptr, buffer) != VK_SUCCESS) return false;
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(device_, *buffer, &req);
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = static_cast<uint32_t>(__builtin_ctz(req.memoryTypeBits));  // any type the buffer takes
    return vkAllocateMemory(device_, &alloc, nullptr, memory) == VK_SUCCESS &&
           vkBindBufferMemory(device_, *buffer, *memory, 0) == VK_SUCCESS;
  }

  // Records with `record` into a fresh command buffer, submits it and waits for it.
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cb = VK_NULL_HANDLE;
    ASSERT_EQ(vkAllocateCommandBuffers(device_, &alloc, &cb), VK_SUCCESS);
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    ASSERT_EQ(vkBeginCommandBuffer(cb, &begin), VK_SUCCESS);
    record(cb);
    ASSERT_EQ(vkEndCommandBuffer(cb), VK_SUCCESS);
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cb;
    ASSERT_EQ(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
    ASSERT_EQ(vkQueueWaitIdle(queue_), VK_SUCCESS);
    vkFreeCommandBuffers(device_, pool_, 1, &cb);
  }

  // Transfer writes -> transfer writes: what the hazard leaves out.
  static void transfer_barrier(VkCommandBuffer cb) {
    VkMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &b, 0, nullptr, 0,
                         nullptr);
  }

  static std::size_t count_containing(const std::vector<std::string>& errors, const char* what) {
    return static_cast<std::size_t>(std::count_if(
        errors.begin(), errors.end(), [&](const std::string& e) { return e.find(what) != std::string::npos; }));
  }

  static constexpr VkDeviceSize kBytes = 4096;
  std::unique_ptr<HeadlessVulkan> vk_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
};

// The positive control: the GPU suites' "no validation errors" checks would see a hazard.
TEST_F(ValidationHarness, TwoFillsWithoutABarrierReportASyncHazard) {
  ASSERT_TRUE(vk_->errors().empty()) << vk_->errors().front();
  submit_and_wait([&](VkCommandBuffer cb) {
    vkCmdFillBuffer(cb, buffer_, 0, kBytes, 1u);
    vkCmdFillBuffer(cb, buffer_, 0, kBytes, 2u);
  });
  const auto errors = vk_->errors();
  ASSERT_FALSE(errors.empty()) << "a write-after-write hazard went unheard";
  EXPECT_GE(count_containing(errors, "SYNC-HAZARD-WRITE-AFTER-WRITE"), 1u) << errors.front();
  std::printf("[ heard ] %s\n", errors.front().substr(0, 160).c_str());
}

// The control's counterpart: the same fills with the barrier are silent, so the
// hazard above is the missing barrier, not the harness complaining about anything.
TEST_F(ValidationHarness, TheSameFillsWithABarrierAreSilent) {
  submit_and_wait([&](VkCommandBuffer cb) {
    vkCmdFillBuffer(cb, buffer_, 0, kBytes, 1u);
    transfer_barrier(cb);
    vkCmdFillBuffer(cb, buffer_, 0, kBytes, 2u);
  });
  const auto errors = vk_->errors();
  EXPECT_TRUE(errors.empty()) << errors.size() << " error(s), the first: " << errors.front();
}

// Messages from several threads are all kept: each thread records its own hazard
// (a buffer of its own, a pool of its own) and submits it, the queue under a lock.
TEST_F(ValidationHarness, HazardsRecordedOnSeveralThreadsAreAllHeard) {
  constexpr int kThreads = 4;
  std::mutex queue_mutex;
  std::vector<std::thread> threads;
  std::vector<bool> recorded(kThreads, false);
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      VkBuffer buffer = VK_NULL_HANDLE;
      VkDeviceMemory memory = VK_NULL_HANDLE;
      VkCommandPool pool = VK_NULL_HANDLE;
      VkCommandPoolCreateInfo pool_info{};
      pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
      pool_info.queueFamilyIndex = vk_->device().queue_family_index;
      VkCommandBuffer cb = VK_NULL_HANDLE;
      VkCommandBufferAllocateInfo alloc{};
      alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
      alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
      alloc.commandBufferCount = 1;
      VkCommandBufferBeginInfo begin{};
      begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
      if (!make_buffer(&buffer, &memory) || vkCreateCommandPool(device_, &pool_info, nullptr, &pool) != VK_SUCCESS)
        return;
      alloc.commandPool = pool;
      if (vkAllocateCommandBuffers(device_, &alloc, &cb) == VK_SUCCESS &&
          vkBeginCommandBuffer(cb, &begin) == VK_SUCCESS) {
        vkCmdFillBuffer(cb, buffer, 0, kBytes, 1u);
        vkCmdFillBuffer(cb, buffer, 0, kBytes, 2u);
        VkSubmitInfo submit{};
        submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cb;
        if (vkEndCommandBuffer(cb) == VK_SUCCESS) {
          std::lock_guard lock(queue_mutex);
          recorded[t] =
              vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE) == VK_SUCCESS && vkQueueWaitIdle(queue_) == VK_SUCCESS;
        }
      }
      vkDestroyCommandPool(device_, pool, nullptr);
      vkDestroyBuffer(device_, buffer, nullptr);
      vkFreeMemory(device_, memory, nullptr);
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(std::count(recorded.begin(), recorded.end(), true), kThreads);
  // One write-after-write per command buffer, recorded on its own thread.
  EXPECT_EQ(count_containing(vk_->errors(), "SYNC-HAZARD-WRITE-AFTER-WRITE"), std::size_t{kThreads});
}

}  // namespace
}  // namespace foveart::layer
