#include "full_frame.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

#include <foveation/elapsed.hpp>
#include <foveation/eye_rays.hpp>
#include <foveation/image.hpp>
#include <foveation/rgba8.hpp>
#include <foveation/temporal_mode.hpp>
#include <foveation/view_settings.hpp>

#include <glm/gtc/quaternion.hpp>

#include "command_pool.hpp"
#include "engine/render.hpp"
#include "gpu_engine/gpu_tracer.hpp"
#include "layer/display_transform_chain.hpp"
#include "layer/sampling_defaults.hpp"

namespace foveart::hello {
namespace {

void check_full_render(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(std::string("full render: ") + what + " failed: VkResult " + std::to_string(r));
}

using foveation::ms_since;

// The view as the layer makes it from a submitted projection view (layer/src/xr_glm.hpp eye_view_of).
FoveartEyeView eye_view(uint32_t eye, const XrPosef& pose, const XrFovf& fov, uint32_t width_px, uint32_t height_px) {
  foveation::EyePose p;
  p.position_m = glm::vec3(pose.position.x, pose.position.y, pose.position.z);
  p.orientation = glm::quat(pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z);
  return foveation::make_eye_view(eye, width_px, height_px, p, fov.angleLeft, fov.angleRight, fov.angleUp,
                                  fov.angleDown);
}

// A buffer and its memory; host-visible ones stay mapped.
struct Buffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;

  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer() { reset(); }
  void reset() {
    if (device == VK_NULL_HANDLE) return;
    if (buffer != VK_NULL_HANDLE) vkDestroyBuffer(device, buffer, nullptr);
    if (memory != VK_NULL_HANDLE) vkFreeMemory(device, memory, nullptr);  // unmaps
    buffer = VK_NULL_HANDLE;
    memory = VK_NULL_HANDLE;
    mapped = nullptr;
    size = 0;
  }
};

// `wanted` memory properties if a type has them, else any type the buffer allows
// (device-local is a preference; host-visible + coherent is required when asked).
uint32_t memory_type(VkPhysicalDevice physical, uint32_t allowed, VkMemoryPropertyFlags required,
                     VkMemoryPropertyFlags preferred) {
  VkPhysicalDeviceMemoryProperties props{};
  vkGetPhysicalDeviceMemoryProperties(physical, &props);
  for (VkMemoryPropertyFlags want : {required | preferred, required}) {
    for (uint32_t i = 0; i < props.memoryTypeCount; ++i) {
      if ((allowed & (1u << i)) != 0 && (props.memoryTypes[i].propertyFlags & want) == want) return i;
    }
  }
  throw std::runtime_error("full render: no Vulkan memory type for a buffer");
}

void create_buffer(const VulkanDevice& d, VkDeviceSize size, VkBufferUsageFlags usage, bool host, Buffer* out) {
  out->reset();
  out->device = d.device;
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check_full_render(vkCreateBuffer(d.device, &info, nullptr, &out->buffer), "vkCreateBuffer");
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(d.device, out->buffer, &req);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      host ? memory_type(d.physical_device, req.memoryTypeBits,
                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0)
           : memory_type(d.physical_device, req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  check_full_render(vkAllocateMemory(d.device, &alloc, nullptr, &out->memory), "vkAllocateMemory");
  check_full_render(vkBindBufferMemory(d.device, out->buffer, out->memory, 0), "vkBindBufferMemory");
  if (host) check_full_render(vkMapMemory(d.device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped), "vkMapMemory");
  out->size = size;
}

class FullFrame final : public ViewRenderer {
 public:
  FullFrame(const VulkanDevice& device, const FullFrameEngine& engine, uint32_t spp,
            const foveation::DisplayTransform& display, foveation::Executor* executor, FullFrameTimes* times)
      : device_(device), engine_(engine), spp_(std::max<uint32_t>(spp, 1)), display_(display),
        executor_(executor), times_(times) {
    try {
      create_objects();
    } catch (...) {
      destroy_objects();
      throw;
    }
  }

  ~FullFrame() override { destroy_objects(); }
  FullFrame(const FullFrame&) = delete;
  FullFrame& operator=(const FullFrame&) = delete;

  void render(uint32_t e, const XrPosef& pose, const XrFovf& fov, VkImage image, uint32_t width_px,
              uint32_t height_px) override {
    const auto t0 = std::chrono::steady_clock::now();
    const FoveartEyeView view = eye_view(e, pose, fov, width_px, height_px);
    const std::size_t pixels = std::size_t(width_px) * height_px;
    // No temporal history: the layer's seed, the same every frame.
    const uint64_t seed =
        foveation::temporal_view_settings(foveation::TemporalMode::off, int(spp_), layer::kSampleSeed).frame_sample_seed(0);
    if (upload_.size < pixels * 4) create_buffer(device_, pixels * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, &upload_);
    double trace_ms = 0.0;
    if (engine_.gpu != nullptr) {
      trace_ms = trace_on_device(view, seed);
    } else {
      engine::RenderSettings settings;
      settings.spp = int(spp_);
      settings.seed = seed;
      const engine::RenderResult r =
          engine::render_full(engine_.trace_rays, engine_.user_data, view, settings, &image_, *executor_);
      if (r.status != FOVEART_RESULT_SUCCESS)
        throw std::runtime_error("full render: the engine failed with status " + std::to_string(r.status));
      trace_ms = r.trace_ms;
    }
    foveation::encode_rgba8(image_, true, display_, static_cast<uint8_t*>(upload_.mapped), *executor_);
    upload(image, width_px, height_px);
    times_->trace_ms[e].push_back(float(trace_ms));
    times_->transfer_encode_ms[e].push_back(float(ms_since(t0) - trace_ms));
  }

 private:
  void create_objects() {
    commands_.create(device_.device, device_.queue_family_index, 1, "full render");
    if (engine_.gpu != nullptr) {
      uint32_t count = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(device_.physical_device, &count, nullptr);
      std::vector<VkQueueFamilyProperties> families(count);
      vkGetPhysicalDeviceQueueFamilyProperties(device_.physical_device, &count, families.data());
      if (device_.queue_family_index >= count || families[device_.queue_family_index].timestampValidBits == 0)
        throw std::runtime_error("full render: the session's queue has no timestamps to time the GPU engine with");
      VkPhysicalDeviceProperties props{};
      vkGetPhysicalDeviceProperties(device_.physical_device, &props);
      timestamp_period_ns_ = props.limits.timestampPeriod;
      VkQueryPoolCreateInfo query{};
      query.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
      query.queryType = VK_QUERY_TYPE_TIMESTAMP;
      query.queryCount = 2;
      check_full_render(vkCreateQueryPool(device_.device, &query, nullptr, &queries_), "vkCreateQueryPool");
    }
  }

  void destroy_objects() noexcept {
    if (queries_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_.device, queries_, nullptr);
    commands_.destroy(device_.device);
    queries_ = VK_NULL_HANDLE;
  }

  // record_full between two timestamps, then a copy into the readback buffer;
  // returns the GPU time of the trace and leaves the linear image in image_.
  double trace_on_device(const FoveartEyeView& view, uint64_t seed) {
    const std::size_t pixels = std::size_t(view.width_px) * view.height_px;
    const VkDeviceSize bytes = pixels * 16;  // vec4 per pixel: rgb, the first hit's distance
    if (out_.size != bytes) {
      create_buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, &out_);
      create_buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, &readback_);
    }
    begin();
    vkCmdResetQueryPool(cb(), queries_, 0, 2);
    vkCmdWriteTimestamp(cb(), VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
    std::string error;
    if (!engine_.gpu->record_full(cb(), view, spp_, seed, out_.buffer, 0, &error)) {
      vkEndCommandBuffer(cb());
      throw std::runtime_error("full render: the GPU engine could not record: " + error);
    }
    vkCmdWriteTimestamp(cb(), VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
    VkBufferMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER;
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.buffer = out_.buffer;
    barrier.size = VK_WHOLE_SIZE;
    // The engine's shader writes (whichever stage its backend writes from) before the copy.
    vkCmdPipelineBarrier(cb(), VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 1,
                         &barrier, 0, nullptr);
    const VkBufferCopy copy{0, 0, bytes};
    vkCmdCopyBuffer(cb(), out_.buffer, readback_.buffer, 1, &copy);
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    barrier.buffer = readback_.buffer;
    vkCmdPipelineBarrier(cb(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &barrier,
                         0, nullptr);
    submit_and_wait();
    uint64_t t[2] = {};
    check_full_render(vkGetQueryPoolResults(device_.device, queries_, 0, 2, sizeof t, t, sizeof(uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    if (image_.width_px != int(view.width_px) || image_.height_px != int(view.height_px))
      image_ = foveation::ImageRgb(int(view.width_px), int(view.height_px));
    const auto* rgbw = static_cast<const float*>(readback_.mapped);
    for (std::size_t p = 0; p < pixels; ++p) std::memcpy(&image_.rgb[p * 3], &rgbw[p * 4], 3 * sizeof(float));
    return double(t[1] - t[0]) * double(timestamp_period_ns_) * 1e-6;
  }

  // The encoded bytes into the swapchain image, left ready for the compositor.
  void upload(VkImage image, uint32_t width_px, uint32_t height_px) {
    begin();
    VkImageMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cb(), VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &barrier);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {width_px, height_px, 1};
    vkCmdCopyBufferToImage(cb(), upload_.buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.newLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    vkCmdPipelineBarrier(cb(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0,
                         nullptr, 0, nullptr, 1, &barrier);
    submit_and_wait();
  }

  void begin() {
    check_full_render(vkResetCommandBuffer(cb(), 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check_full_render(vkBeginCommandBuffer(cb(), &begin), "vkBeginCommandBuffer");
  }

  void submit_and_wait() {
    check_full_render(vkEndCommandBuffer(cb()), "vkEndCommandBuffer");
    check_full_render(vkResetFences(device_.device, 1, &commands_.fences[0]), "vkResetFences");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commands_.buffers[0];
    check_full_render(vkQueueSubmit(device_.queue, 1, &submit, commands_.fences[0]), "vkQueueSubmit");
    check_full_render(vkWaitForFences(device_.device, 1, &commands_.fences[0], VK_TRUE, UINT64_MAX), "vkWaitForFences");
  }

  VulkanDevice device_;
  FullFrameEngine engine_;
  uint32_t spp_;
  foveation::DisplayTransform display_;
  foveation::Executor* executor_;
  FullFrameTimes* times_;
  CommandPool commands_;  // one command buffer and its fence
  VkCommandBuffer cb() const { return commands_.buffers[0]; }
  VkQueryPool queries_ = VK_NULL_HANDLE;
  float timestamp_period_ns_ = 1.0f;
  Buffer out_, readback_, upload_;  // the GPU engine's linear image, its host copy, the encoded bytes
  foveation::ImageRgb image_;       // the linear image of the view being drawn
};

}  // namespace

foveation::DisplayTransform display_for(float exposure, XrFoveatedToneMapFOVEART tone_map) {
  const XrFoveatedDisplayTransformFOVEART chained{XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART, nullptr, exposure, tone_map};
  std::string error;
  // Over the layer config's defaults (exposure 1, pbr-neutral): DisplayTransform's own.
  const foveation::DisplayTransform d = layer::resolve_display(&chained, foveation::DisplayTransform{}, &error);
  if (!error.empty()) throw std::invalid_argument(error);
  return d;
}

std::unique_ptr<ViewRenderer> make_full_frame(const VulkanDevice& device, const FullFrameEngine& engine,
                                              uint32_t spp, const foveation::DisplayTransform& display,
                                              foveation::Executor* executor, FullFrameTimes* times) {
  if ((engine.gpu == nullptr) == (engine.trace_rays == nullptr))
    throw std::invalid_argument("full render: give the CPU engine's callback or the GPU engine, one of them");
  return std::make_unique<FullFrame>(device, engine, spp, display, executor, times);
}

}  // namespace foveart::hello
