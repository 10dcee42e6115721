// Swapchains backed by real VkImages on the application's device, with the
// acquire / wait / release state checks of the spec (section 10.1).
#include "api_common.h"

namespace foveart::sim {
namespace {

constexpr uint32_t kImageCount = 3;

// Preferred first (hello_xr and most engines take the first they know).
const std::vector<int64_t>& swapchain_formats(const Config& config) {
  static const std::vector<int64_t> formats{VK_FORMAT_R8G8B8A8_SRGB,  VK_FORMAT_B8G8R8A8_SRGB,
                                            VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM,
                                            VK_FORMAT_D32_SFLOAT,     VK_FORMAT_D16_UNORM};
  static const std::vector<int64_t> float_formats{VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_D32_SFLOAT,
                                                  VK_FORMAT_D16_UNORM};
  return config.float_formats_only ? float_formats : formats;
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_swapchain_formats(XrSession handle, uint32_t capacity,
                                                           uint32_t* count, int64_t* formats) {
  return guarded("xrEnumerateSwapchainFormats", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)session;
    return two_call(capacity, count, formats, swapchain_formats(inst->config));
  });
}

VkImageUsageFlags vk_usage(XrSwapchainUsageFlags u, bool depth) {
  VkImageUsageFlags v = 0;
  if (u & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT) v |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  if (u & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)
    v |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  if (u & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT) v |= VK_IMAGE_USAGE_STORAGE_BIT;
  if (u & XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT) v |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  if (u & XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT) v |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  if (u & XR_SWAPCHAIN_USAGE_SAMPLED_BIT) v |= VK_IMAGE_USAGE_SAMPLED_BIT;
  if (u & XR_SWAPCHAIN_USAGE_INPUT_ATTACHMENT_BIT_MND) v |= VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT;
  // The compositor (capture) reads colour images back; a real one would sample them.
  if (!depth) v |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  return v;
}

XRAPI_ATTR XrResult XRAPI_CALL create_swapchain(XrSession handle, const XrSwapchainCreateInfo* info,
                                                XrSwapchain* out) {
  return guarded("xrCreateSwapchain", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_SWAPCHAIN_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    const auto& formats = swapchain_formats(inst->config);
    if (std::find(formats.begin(), formats.end(), info->format) == formats.end()) {
      return XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED;
    }
    if (info->createFlags & XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT)
      return XR_ERROR_FEATURE_UNSUPPORTED;
    if (info->width == 0 || info->height == 0 || info->arraySize == 0 || info->mipCount == 0 ||
        info->sampleCount == 0 || (info->faceCount != 1 && info->faceCount != 6)) {
      return XR_ERROR_VALIDATION_FAILURE;
    }
    if (info->faceCount != 1 || info->sampleCount != 1 || info->width > 4096 ||
        info->height > 4096) {
      return XR_ERROR_FEATURE_UNSUPPORTED;
    }
    const auto format = static_cast<VkFormat>(info->format);
    const bool depth = is_depth_format(format);
    const VkImageUsageFlags usage = vk_usage(info->usageFlags, depth);
    const VkImageCreateFlags flags = (info->usageFlags & XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT)
                                         ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT
                                         : 0;
    if (!session->vk.supports(format, usage, flags, info->arraySize))
      return XR_ERROR_FEATURE_UNSUPPORTED;
    auto sc = std::make_unique<Swapchain>();
    sc->session = handle;
    sc->info = *info;
    sc->info.next = nullptr;
    sc->is_depth = depth;
    const uint32_t n = (info->createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) ? 1 : kImageCount;
    sc->images.resize(n);
    for (auto& img : sc->images) {
      std::string error;
      if (!session->vk.create_image(format, info->width, info->height, info->arraySize,
                                    info->mipCount, usage, flags, img, &error)) {
        log(LogLevel::Error, "xrCreateSwapchain: " + error);
        for (auto& i : sc->images) session->vk.destroy_image(i);
        return XR_ERROR_OUT_OF_MEMORY;
      }
    }
    sc->id = rt.next_id++;
    *out = to_handle<XrSwapchain>(sc->id);
    rt.swapchains.emplace(sc->id, std::move(sc));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_swapchain(XrSwapchain handle) {
  return guarded("xrDestroySwapchain", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Swapchain* sc = find(rt.swapchains, handle);
    if (sc == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (Session* s = find(rt.sessions, sc->session)) {
      for (auto& img : sc->images) s->vk.destroy_image(img);
    }
    rt.swapchains.erase(handle_id(handle));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_swapchain_images(XrSwapchain handle, uint32_t capacity,
                                                          uint32_t* count,
                                                          XrSwapchainImageBaseHeader* images) {
  return guarded("xrEnumerateSwapchainImages", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Swapchain* sc = find(rt.swapchains, handle);
    if (sc == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (count == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    const auto n = static_cast<uint32_t>(sc->images.size());
    *count = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (images == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    auto* vk_images = reinterpret_cast<XrSwapchainImageVulkanKHR*>(images);
    for (uint32_t i = 0; i < n; ++i) {
      if (vk_images[i].type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR)
        return XR_ERROR_VALIDATION_FAILURE;
      vk_images[i].image = sc->images[i].image;
    }
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL acquire_swapchain_image(XrSwapchain handle,
                                                       const XrSwapchainImageAcquireInfo* info,
                                                       uint32_t* index) {
  return guarded("xrAcquireSwapchainImage", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Swapchain* sc = find(rt.swapchains, handle);
    if (sc == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (info != nullptr && info->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO)
      return XR_ERROR_VALIDATION_FAILURE;
    if (index == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    Session* session = find(rt.sessions, sc->session);
    if (session == nullptr) return XR_ERROR_HANDLE_INVALID;
    const bool is_static = (sc->info.createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) != 0;
    if (is_static && sc->acquire_count > 0) return XR_ERROR_CALL_ORDER_INVALID;
    if (sc->acquired.size() >= sc->images.size()) return XR_ERROR_CALL_ORDER_INVALID;
    const uint32_t i = sc->next_index;
    SwapchainImage& img = sc->images[i];
    if (!img.initialized &&
        !session->vk.initialize_layout(img, sc->is_depth, sc->info.arraySize, sc->info.mipCount)) {
      return XR_ERROR_RUNTIME_FAILURE;
    }
    sc->next_index = (i + 1) % static_cast<uint32_t>(sc->images.size());
    sc->acquired.push_back(i);
    ++sc->acquire_count;
    *index = i;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL wait_swapchain_image(XrSwapchain handle,
                                                    const XrSwapchainImageWaitInfo* info) {
  return guarded("xrWaitSwapchainImage", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Swapchain* sc = find(rt.swapchains, handle);
    if (sc == nullptr) return XR_ERROR_HANDLE_INVALID;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
    // Only the oldest acquired image may be waited, and only once before release.
    if (sc->acquired.empty() || sc->front_waited) return XR_ERROR_CALL_ORDER_INVALID;
    sc->front_waited = true;  // the compositor never holds images: always ready
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL release_swapchain_image(XrSwapchain handle,
                                                       const XrSwapchainImageReleaseInfo* info) {
  return guarded("xrReleaseSwapchainImage", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Swapchain* sc = find(rt.swapchains, handle);
    if (sc == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (info != nullptr && info->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO)
      return XR_ERROR_VALIDATION_FAILURE;
    if (sc->acquired.empty() || !sc->front_waited) return XR_ERROR_CALL_ORDER_INVALID;
    sc->last_released = sc->acquired.front();
    sc->acquired.pop_front();
    sc->front_waited = false;
    return XR_SUCCESS;
  });
}

}  // namespace

void register_swapchain_functions(FunctionTable& t) {
  add(t, "xrEnumerateSwapchainFormats", &enumerate_swapchain_formats);
  add(t, "xrCreateSwapchain", &create_swapchain);
  add(t, "xrDestroySwapchain", &destroy_swapchain);
  add(t, "xrEnumerateSwapchainImages", &enumerate_swapchain_images);
  add(t, "xrAcquireSwapchainImage", &acquire_swapchain_image);
  add(t, "xrWaitSwapchainImage", &wait_swapchain_image);
  add(t, "xrReleaseSwapchainImage", &release_swapchain_image);
}

}  // namespace foveart::sim
