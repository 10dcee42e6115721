#include "eye_swapchain.hpp"

#include <algorithm>

#include "gpu/vk_util.hpp"

namespace foveart::layer {
using gpu::vk_error;
using gpu::vk_struct;
namespace {

std::string xr_error(const char* what, XrResult r) { return std::string(what) + " failed (XrResult " + std::to_string(r) + ")"; }
template <class T>
T xr_struct(XrStructureType type) {
  T s{};
  s.type = type;
  return s;
}

// Formats we can fill from RGBA8 bytes, best first.
int format_rank(int64_t format) {
  switch (format) {
    case VK_FORMAT_R8G8B8A8_SRGB: return 0;
    case VK_FORMAT_R8G8B8A8_UNORM: return 1;
    default: return -1;
  }
}

}  // namespace

std::unique_ptr<EyeSwapchain> EyeSwapchain::create(const SessionState& session, uint32_t width_px,
                                                   uint32_t height_px, std::string* error) {
  std::unique_ptr<EyeSwapchain> sc(new EyeSwapchain());
  sc->instance_ = session.instance;
  sc->next_ = &session.instance->next;
  sc->device_ = session.vk_device;
  sc->width_px_ = width_px;
  sc->height_px_ = height_px;
  const NextDispatch& next = *sc->next_;

  uint32_t count = 0;
  XrResult r = next.EnumerateSwapchainFormats(session.handle, 0, &count, nullptr);
  if (XR_FAILED(r)) return *error = xr_error("xrEnumerateSwapchainFormats", r), nullptr;
  std::vector<int64_t> formats(count);
  r = next.EnumerateSwapchainFormats(session.handle, count, &count, formats.data());
  if (XR_FAILED(r)) return *error = xr_error("xrEnumerateSwapchainFormats", r), nullptr;
  int64_t chosen = -1;
  for (int64_t f : formats) {
    if (format_rank(f) >= 0 && (chosen < 0 || format_rank(f) < format_rank(chosen))) chosen = f;
  }
  if (chosen < 0) return *error = "the runtime offers no RGBA8 swapchain format", nullptr;
  sc->srgb_ = chosen == VK_FORMAT_R8G8B8A8_SRGB;

  XrSwapchainCreateInfo info{};
  info.type = XR_TYPE_SWAPCHAIN_CREATE_INFO;
  info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
  info.format = chosen;
  info.sampleCount = 1;
  info.width = width_px;
  info.height = height_px;
  info.faceCount = 1;
  info.arraySize = 1;
  info.mipCount = 1;
  r = next.CreateSwapchain(session.handle, &info, &sc->swapchain_);
  if (XR_FAILED(r)) return *error = xr_error("xrCreateSwapchain", r), nullptr;
  r = next.EnumerateSwapchainImages(sc->swapchain_, 0, &count, nullptr);
  if (XR_FAILED(r) || count == 0) return *error = xr_error("xrEnumerateSwapchainImages", r), nullptr;
  std::vector<XrSwapchainImageVulkanKHR> images(count, xr_struct<XrSwapchainImageVulkanKHR>(XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR));
  r = next.EnumerateSwapchainImages(sc->swapchain_, count, &count,
                                    reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data()));
  if (XR_FAILED(r)) return *error = xr_error("xrEnumerateSwapchainImages", r), nullptr;
  for (const auto& image : images) sc->images_.push_back(image.image);

  sc->physical_device_ = session.vk_physical_device;
  VkResult vr = VK_SUCCESS;
  vkGetDeviceQueue(sc->device_, session.vk_queue_family_index, session.vk_queue_index, &sc->queue_);
  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = session.vk_queue_family_index;
  vr = vkCreateCommandPool(sc->device_, &pool_info, nullptr, &sc->pool_);
  if (vr != VK_SUCCESS) return *error = vk_error("vkCreateCommandPool", vr), nullptr;
  auto cb_info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cb_info.commandPool = sc->pool_;
  cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_info.commandBufferCount = 1;
  vr = vkAllocateCommandBuffers(sc->device_, &cb_info, &sc->command_buffer_);
  if (vr != VK_SUCCESS) return *error = vk_error("vkAllocateCommandBuffers", vr), nullptr;
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  vr = vkCreateFence(sc->device_, &fence_info, nullptr, &sc->fence_);
  if (vr != VK_SUCCESS) return *error = vk_error("vkCreateFence", vr), nullptr;
  return sc;
}

EyeSwapchain::~EyeSwapchain() {
  if (device_ != VK_NULL_HANDLE) {
    if (fence_ != VK_NULL_HANDLE) vkDestroyFence(device_, fence_, nullptr);
    if (pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, pool_, nullptr);
    if (mapped_ != nullptr) vkUnmapMemory(device_, memory_);
    if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
  }
  if (swapchain_ != XR_NULL_HANDLE && next_ != nullptr) next_->DestroySwapchain(swapchain_);
}

bool EyeSwapchain::create_staging(std::string* error) {
  // Host-visible staging buffer, persistently mapped.
  VkPhysicalDeviceMemoryProperties memory{};
  vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory);
  return gpu::create_bound_buffer(device_, memory, VkDeviceSize{width_px_} * height_px_ * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                             VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, &buffer_,
                             &memory_, &mapped_, error);
}

uint8_t* EyeSwapchain::staging(std::string* error) {
  if (mapped_ == nullptr && !create_staging(error)) return nullptr;
  return static_cast<uint8_t*>(mapped_);
}


bool EyeSwapchain::upload(std::string* error) {
  if (mapped_ == nullptr) return *error = "upload before the staging buffer was written", false;
  return present(
      [this](VkCommandBuffer cb, VkImage image, std::string*) {
        gpu::record_copy_to_image(cb, buffer_, image, width_px_, height_px_);
        return true;
      },
      error);
}

bool EyeSwapchain::acquire(VkImage* image, std::string* error) {
  uint32_t index = 0;
  auto acquire = xr_struct<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
  XrResult r = next_->AcquireSwapchainImage(swapchain_, &acquire, &index);
  if (XR_FAILED(r) || index >= images_.size()) return *error = xr_error("xrAcquireSwapchainImage", r), false;
  auto wait = xr_struct<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
  wait.timeout = XR_INFINITE_DURATION;
  r = next_->WaitSwapchainImage(swapchain_, &wait);
  if (XR_FAILED(r)) {
    *error = xr_error("xrWaitSwapchainImage", r);
    std::string ignored;
    (void)release(&ignored);
    return false;
  }
  *image = images_[index];
  return true;
}

bool EyeSwapchain::release(std::string* error) {
  auto release = xr_struct<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
  const XrResult r = next_->ReleaseSwapchainImage(swapchain_, &release);
  if (XR_FAILED(r)) return *error = xr_error("xrReleaseSwapchainImage", r), false;
  return true;
}

bool EyeSwapchain::present(const RecordFn& record, std::string* error) {
  VkImage image = VK_NULL_HANDLE;
  if (!acquire(&image, error)) return false;
  std::string ignored;
  VkResult vr = vkResetCommandBuffer(command_buffer_, 0);
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (vr == VK_SUCCESS) vr = vkBeginCommandBuffer(command_buffer_, &begin);
  bool recorded = false;
  if (vr == VK_SUCCESS) {
    recorded = record(command_buffer_, image, error);
    vr = vkEndCommandBuffer(command_buffer_);
  }
  if (!recorded && vr == VK_SUCCESS) {  // nothing submitted: the image goes back as it was
    (void)release(&ignored);
    return false;
  }
  if (vr == VK_SUCCESS) vr = vkResetFences(device_, 1, &fence_);
  if (vr == VK_SUCCESS) {
    auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &command_buffer_;
    vr = vkQueueSubmit(queue_, 1, &submit, fence_);
  }
  if (vr == VK_SUCCESS) vr = vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX);
  const bool released = release(vr == VK_SUCCESS ? error : &ignored);
  if (vr != VK_SUCCESS) return *error = vk_error("frame commands", vr), false;
  return released;
}

}  // namespace foveart::layer
