// xrCreateVulkanDeviceKHR through the layer: what the app enabled on its
// device (bufferDeviceAddress, timelineSemaphore) is recorded for the device
// it got, from any of the structs that can enable it, and nothing else.
#include <gtest/gtest.h>

#include "state.hpp"
#include "vulkan_device.hpp"

namespace foveart::layer {
namespace {

VkDevice vk_device_handle(uintptr_t id) { return reinterpret_cast<VkDevice>(id); }
XrInstance xr_instance_handle(uintptr_t id) { return reinterpret_cast<XrInstance>(id); }

VkDeviceCreateInfo device_info(const void* next) {
  VkDeviceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  info.pNext = next;
  return info;
}

TEST(VulkanDeviceFeatures, Vulkan12FeaturesEnableBoth) {
  VkPhysicalDeviceVulkan12Features v12{};
  v12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  v12.bufferDeviceAddress = VK_TRUE;
  VkDeviceCreateInfo info = device_info(&v12);
  VulkanDeviceFeatures f = enabled_device_features(&info);
  EXPECT_TRUE(f.buffer_device_address);
  EXPECT_FALSE(f.timeline_semaphore);
  v12.timelineSemaphore = VK_TRUE;
  v12.bufferDeviceAddress = VK_FALSE;
  f = enabled_device_features(&info);
  EXPECT_FALSE(f.buffer_device_address);
  EXPECT_TRUE(f.timeline_semaphore);
}

TEST(VulkanDeviceFeatures, SeparateFeatureStructsAnywhereInTheChain) {
  VkPhysicalDeviceTimelineSemaphoreFeatures timeline{};
  timeline.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES;
  timeline.timelineSemaphore = VK_TRUE;
  VkPhysicalDeviceBufferDeviceAddressFeatures address{};
  address.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES;
  address.pNext = &timeline;
  address.bufferDeviceAddress = VK_TRUE;
  VkPhysicalDeviceFeatures2 features2{};  // a struct the walk does not know, first
  features2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  features2.pNext = &address;
  VkDeviceCreateInfo info = device_info(&features2);
  const VulkanDeviceFeatures f = enabled_device_features(&info);
  EXPECT_TRUE(f.buffer_device_address);
  EXPECT_TRUE(f.timeline_semaphore);
}

TEST(VulkanDeviceFeatures, NothingChainedOrNoInfoEnablesNothing) {
  VkDeviceCreateInfo info = device_info(nullptr);
  EXPECT_FALSE(enabled_device_features(&info).buffer_device_address);
  EXPECT_FALSE(enabled_device_features(&info).timeline_semaphore);
  EXPECT_FALSE(enabled_device_features(nullptr).buffer_device_address);
}

// The next link's xrCreateVulkanDeviceKHR: hands out the device 0x5e5 and succeeds.
XRAPI_ATTR XrResult XRAPI_CALL fake_create_vulkan_device(XrInstance, const XrVulkanDeviceCreateInfoKHR*,
                                                          VkDevice* device, VkResult* vk_result) {
  *device = vk_device_handle(0x5e5);
  *vk_result = VK_SUCCESS;
  return XR_SUCCESS;
}

TEST(VulkanDeviceFeatures, TheHookRecordsTheCreatedDeviceUntilItsInstanceGoes) {
  const XrInstance instance = xr_instance_handle(0x1e5);
  auto state = std::make_shared<InstanceState>();
  state->handle = instance;
  state->next.CreateVulkanDeviceKHR = &fake_create_vulkan_device;
  Registry::get().add_instance(state);

  VkPhysicalDeviceVulkan12Features v12{};
  v12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  v12.bufferDeviceAddress = VK_TRUE;
  v12.timelineSemaphore = VK_TRUE;
  const VkDeviceCreateInfo vk_info = device_info(&v12);
  XrVulkanDeviceCreateInfoKHR info{};
  info.type = XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR;
  info.vulkanCreateInfo = &vk_info;
  VkDevice device = VK_NULL_HANDLE;
  VkResult vk_result = VK_ERROR_UNKNOWN;
  ASSERT_EQ(hook_xrCreateVulkanDeviceKHR(instance, &info, &device, &vk_result), XR_SUCCESS);
  EXPECT_EQ(device, vk_device_handle(0x5e5));
  EXPECT_TRUE(Registry::get().vulkan_device(device).buffer_device_address);
  EXPECT_TRUE(Registry::get().vulkan_device(device).timeline_semaphore);
  EXPECT_FALSE(Registry::get().vulkan_device(vk_device_handle(0x6e6)).buffer_device_address) << "another device";

  Registry::get().remove_instance(instance);
  EXPECT_FALSE(Registry::get().vulkan_device(device).buffer_device_address);
  EXPECT_EQ(hook_xrCreateVulkanDeviceKHR(instance, &info, &device, &vk_result), XR_ERROR_HANDLE_INVALID);
}

}  // namespace
}  // namespace foveart::layer
