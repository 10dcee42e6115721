// XR_KHR_vulkan_enable2 (and the older XR_KHR_vulkan_enable): requirements,
// creating the app's VkInstance/VkDevice, choosing the physical device.
#include <cstring>

#include "api_common.h"

namespace foveart::sim {
namespace {

constexpr XrVersion kMinVulkan = XR_MAKE_VERSION(1, 0, 0);
constexpr XrVersion kMaxVulkan = XR_MAKE_VERSION(1, 3, 0);

XrResult fill_requirements(Instance& inst, XrSystemId system,
                           XrGraphicsRequirementsVulkanKHR* req) {
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  FOVEART_CHECK_STRUCT(req, XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN_KHR);
  req->minApiVersionSupported = kMinVulkan;
  req->maxApiVersionSupported = kMaxVulkan;
  inst.graphics_requirements_queried = true;
  return XR_SUCCESS;
}

// First physical device, preferring a CPU device (lavapipe) only when nothing
// else is present: with VK_ICD_FILENAMES pointing at lavapipe that is all there is.
XrResult pick_physical_device(VkInstance vk_instance, VkPhysicalDevice* out) {
  if (vk_instance == VK_NULL_HANDLE || out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  auto enumerate = reinterpret_cast<PFN_vkEnumeratePhysicalDevices>(
      vkGetInstanceProcAddr(vk_instance, "vkEnumeratePhysicalDevices"));
  if (enumerate == nullptr) return XR_ERROR_RUNTIME_FAILURE;
  uint32_t n = 0;
  if (enumerate(vk_instance, &n, nullptr) != VK_SUCCESS || n == 0) {
    log(LogLevel::Error, "no Vulkan physical device (is VK_ICD_FILENAMES set to lavapipe?)");
    return XR_ERROR_RUNTIME_FAILURE;
  }
  std::vector<VkPhysicalDevice> devices(n);
  enumerate(vk_instance, &n, devices.data());
  *out = devices[0];
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL get_requirements2(XrInstance instance, XrSystemId system,
                                                 XrGraphicsRequirementsVulkan2KHR* req) {
  return guarded("xrGetVulkanGraphicsRequirements2KHR", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    return fill_requirements(*inst, system, req);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_requirements(XrInstance instance, XrSystemId system,
                                                XrGraphicsRequirementsVulkanKHR* req) {
  return guarded("xrGetVulkanGraphicsRequirementsKHR", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    return fill_requirements(*inst, system, req);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL create_vulkan_instance(XrInstance instance,
                                                      const XrVulkanInstanceCreateInfoKHR* info,
                                                      VkInstance* vk_instance,
                                                      VkResult* vk_result) {
  return guarded("xrCreateVulkanInstanceKHR", [&]() -> XrResult {
    {
      FOVEART_LOCK_INSTANCE(instance);
      (void)inst;
    }
    FOVEART_CHECK_STRUCT(info, XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR);
    if (info->systemId != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (info->createFlags != 0 || info->pfnGetInstanceProcAddr == nullptr ||
        info->vulkanCreateInfo == nullptr || vk_instance == nullptr || vk_result == nullptr) {
      return XR_ERROR_VALIDATION_FAILURE;
    }
    auto create = reinterpret_cast<PFN_vkCreateInstance>(
        info->pfnGetInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance"));
    if (create == nullptr) return XR_ERROR_RUNTIME_FAILURE;
    // The runtime needs no instance extensions of its own.
    *vk_result = create(info->vulkanCreateInfo, info->vulkanAllocator, vk_instance);
    if (*vk_result == VK_SUCCESS) {
      std::lock_guard<std::mutex> lock(runtime().mutex);
      if (runtime().instance) runtime().instance->vk_instance = *vk_instance;
    }
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL create_vulkan_device(XrInstance instance,
                                                    const XrVulkanDeviceCreateInfoKHR* info,
                                                    VkDevice* device, VkResult* vk_result) {
  return guarded("xrCreateVulkanDeviceKHR", [&]() -> XrResult {
    {
      FOVEART_LOCK_INSTANCE(instance);
      (void)inst;
    }
    FOVEART_CHECK_STRUCT(info, XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR);
    if (info->systemId != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (info->createFlags != 0 || info->pfnGetInstanceProcAddr == nullptr ||
        info->vulkanCreateInfo == nullptr || info->vulkanPhysicalDevice == VK_NULL_HANDLE ||
        device == nullptr || vk_result == nullptr) {
      return XR_ERROR_VALIDATION_FAILURE;
    }
    // Use the VkInstance made by xrCreateVulkanInstanceKHR through the app's
    // pointer; an instance the app made itself goes through the loader's trampoline.
    VkInstance vk_instance = VK_NULL_HANDLE;
    {
      std::lock_guard<std::mutex> lock(runtime().mutex);
      if (runtime().instance) vk_instance = runtime().instance->vk_instance;
    }
    PFN_vkCreateDevice create = nullptr;
    if (vk_instance != VK_NULL_HANDLE) {
      create = reinterpret_cast<PFN_vkCreateDevice>(
          info->pfnGetInstanceProcAddr(vk_instance, "vkCreateDevice"));
    }
    if (create == nullptr) create = &vkCreateDevice;
    *vk_result =
        create(info->vulkanPhysicalDevice, info->vulkanCreateInfo, info->vulkanAllocator, device);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_graphics_device2(XrInstance instance,
                                                    const XrVulkanGraphicsDeviceGetInfoKHR* info,
                                                    VkPhysicalDevice* out) {
  return guarded("xrGetVulkanGraphicsDevice2KHR", [&]() -> XrResult {
    {
      FOVEART_LOCK_INSTANCE(instance);
      (void)inst;
    }
    FOVEART_CHECK_STRUCT(info, XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR);
    if (info->systemId != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    return pick_physical_device(info->vulkanInstance, out);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_graphics_device(XrInstance instance, XrSystemId system,
                                                   VkInstance vk_instance, VkPhysicalDevice* out) {
  return guarded("xrGetVulkanGraphicsDeviceKHR", [&]() -> XrResult {
    {
      FOVEART_LOCK_INSTANCE(instance);
      (void)inst;
    }
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    return pick_physical_device(vk_instance, out);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_extensions(XrInstance instance, XrSystemId system,
                                              uint32_t capacity, uint32_t* count, char* buffer) {
  return guarded("xrGetVulkan*ExtensionsKHR", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    return two_call_string(capacity, count, buffer, "");  // none needed
  });
}

}  // namespace

void register_vulkan_functions(FunctionTable& t) {
  add(t, "xrGetVulkanGraphicsRequirements2KHR", &get_requirements2, Extension::Vulkan2);
  add(t, "xrCreateVulkanInstanceKHR", &create_vulkan_instance, Extension::Vulkan2);
  add(t, "xrCreateVulkanDeviceKHR", &create_vulkan_device, Extension::Vulkan2);
  add(t, "xrGetVulkanGraphicsDevice2KHR", &get_graphics_device2, Extension::Vulkan2);
  add(t, "xrGetVulkanGraphicsRequirementsKHR", &get_requirements, Extension::Vulkan);
  add(t, "xrGetVulkanGraphicsDeviceKHR", &get_graphics_device, Extension::Vulkan);
  add(t, "xrGetVulkanInstanceExtensionsKHR", &get_extensions, Extension::Vulkan);
  add(t, "xrGetVulkanDeviceExtensionsKHR", &get_extensions, Extension::Vulkan);
}

}  // namespace foveart::sim
