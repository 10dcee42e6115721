#include "gpu_reconstruction.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <iterator>

#include "eye_swapchain.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/shader_constants.h"
#include "shader_depth.hpp"
#include "shaders/encode.spv.h"
#include "shaders/gather.spv.h"
#include "shaders/scatter.spv.h"
#include "shaders/temporal.spv.h"
#include "vk_util.hpp"

namespace foveart::layer {
namespace {

// Push constants, laid out as the shaders declare them (std430).
struct GatherPush {
  int32_t screen_px[2];
  int32_t canvas_offset_px[2];
  int32_t canvas_px[2];
  int32_t first_tile[2];
  int32_t k;
  int32_t neighbor_k;
  uint32_t flags;
  uint32_t chunk_count;
  float fallback_rgb[4];
  uint32_t chunk_first_row[kMaxGpuChunks];
};
static_assert(sizeof(GatherPush) == 128, "shaders/gather.comp push constants");
struct TemporalPush {
  int32_t size_px[2];
  float current_weight;
  float variance_gamma;
  uint32_t constraint;
  uint32_t reset;
  float clip_floor;
  uint32_t reproject;         // 0 no, 1 bilinear, 2 Catmull-Rom (foveation::HistorySampling)
  float last_from_view_q[4];  // xyzw
  float last_from_view_t[4];
  float tan_view[4];  // left, right, up, down
  float tan_last[4];
};
static_assert(sizeof(TemporalPush) == 96, "shaders/temporal.comp push constants");

struct EncodePush {
  int32_t size_px[2];
  uint32_t srgb;
  float exposure;
  uint32_t tone_map;  // FOVEART_TONE_MAP_*
};
struct ScatterPush {
  uint32_t count;
  uint32_t point_count;
};
enum GatherFlags : uint32_t {
  kWeighted = FOVEART_GATHER_WEIGHTED,
  kF16 = FOVEART_GATHER_F16,
  kClampTaps = FOVEART_GATHER_CLAMP_TAPS,
  kClampBlock = FOVEART_GATHER_CLAMP_BLOCK,
  kRbf = FOVEART_GATHER_RBF,
};

enum Binding : uint32_t {
  kChunks = 0,
  kColors,
  kCurrent,
  kHistoryIn,
  kHistoryOut,
  kUpload,
  kEncoded,
  kPointDepth,
  kBindings
};
// The table chunks' array, then one buffer per binding.
constexpr uint32_t kDescriptorCounts[kBindings] = {uint32_t(kMaxGpuChunks), 1, 1, 1, 1, 1, 1, 1};
constexpr uint32_t kQueries = 5;  // timestamps: start, scattered, gathered, accumulated, encoded


uint32_t groups(uint32_t n, uint32_t size) {
  return (n + size - 1) / size;
}

}  // namespace

std::string gpu_unsupported_reason(VkPhysicalDevice physical_device, uint32_t queue_family_index) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, families.data());
  if (queue_family_index >= count) return "the session's queue family does not exist";
  if ((families[queue_family_index].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0) {
    return "the session's queue family has no compute";
  }
  VkPhysicalDeviceFeatures features{};
  vkGetPhysicalDeviceFeatures(physical_device, &features);
  if (!features.shaderStorageBufferArrayDynamicIndexing) {
    return "the device lacks shaderStorageBufferArrayDynamicIndexing (table chunks)";
  }
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physical_device, &properties);
  if (VK_API_VERSION_MINOR(properties.apiVersion) < 1 && VK_API_VERSION_MAJOR(properties.apiVersion) == 1) {
    return "the device is Vulkan 1.0; the shaders are SPIR-V 1.3 (Vulkan 1.1)";
  }
  if (properties.limits.maxPerStageDescriptorStorageBuffers < kMaxGpuChunks + kBindings - 1) {
    return "the device binds fewer than " + std::to_string(kMaxGpuChunks + kBindings - 1) +
           " storage buffers per stage";
  }
  return {};
}

GpuFrame GpuFrame::of(const GpuTables& tables, const foveation::FrameHandOff& frame, bool srgb) {
  const foveation::TracedPoints& traced = *frame.traced;
  const foveation::TemporalFrame& temporal = frame.temporal;
  GpuFrame f;
  f.tables = &tables;
  f.colors = &traced.colors;
  f.point_depth_m = &traced.depth_m;
  f.traced = traced.runs;
  f.mapping = frame.mapping;
  f.rbf_clamp = frame.rbf_clamp;
  f.temporal_reset = temporal.reset;
  f.blend = temporal.blend;  // current_weight: this frame's, the CPU's weight rule for both paths
  f.view = frame.view;
  f.history_view = temporal.history_view;
  f.srgb = srgb;
  // A render cache reprojects its rays itself; its frame has no history_view.
  if (temporal.rays) {
    GpuRayCacheFrame c;
    c.rays = &traced.rays;
    c.pixels = temporal.ray_pixels;
    c.restart = temporal.ray_restart;
    c.filter = temporal.ray_filter;
    c.max_age_frames = temporal.ray_max_age_frames;
    f.ray_cache = c;
  }
  return f;
}

// ---- GpuReconstructor ---------------------------------------------------------

std::unique_ptr<GpuReconstructor> GpuReconstructor::create(const GpuDevice& device, std::string* error) {
  if (std::string why = gpu_unsupported_reason(device.physical_device, device.queue_family_index); !why.empty()) {
    return *error = why, nullptr;
  }
  std::unique_ptr<GpuReconstructor> g(new GpuReconstructor());
  g->device_ = device;
  VkDevice dev = device.device;
  vkGetDeviceQueue(dev, device.queue_family_index, device.queue_index, &g->queue_);
  vkGetPhysicalDeviceMemoryProperties(device.physical_device, &g->memory_properties_);
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device.physical_device, &properties);
  g->max_chunk_bytes_ = properties.limits.maxStorageBufferRange;
  g->storage_alignment_ = std::max<VkDeviceSize>(4, properties.limits.minStorageBufferOffsetAlignment);
  g->timestamp_period_ns_ = properties.limits.timestampPeriod;
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical_device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical_device, &count, families.data());
  g->timestamps_ = families[device.queue_family_index].timestampValidBits > 0;

  if (!create_storage_pipeline_layout(dev, kDescriptorCounts, kBindings, sizeof(GatherPush), &g->set_layout_,
                                      &g->pipeline_layout_, error)) {
    return nullptr;
  }

  struct Stage {
    const uint32_t* code;
    size_t bytes;
    VkPipeline* pipeline;
  };
  const Stage stages[] = {{foveart_scatter_spv, sizeof foveart_scatter_spv, &g->scatter_},
                          {foveart_gather_spv, sizeof foveart_gather_spv, &g->gather_},
                          {foveart_temporal_spv, sizeof foveart_temporal_spv, &g->temporal_},
                          {foveart_encode_spv, sizeof foveart_encode_spv, &g->encode_}};
  for (const Stage& s : stages) {
    if (!create_compute_pipeline(dev, g->pipeline_layout_, s.code, s.bytes, s.pipeline, error)) return nullptr;
  }
  g->ray_cache_ = GpuRayCachePipelines::create(dev, error);
  if (g->ray_cache_ == nullptr) return nullptr;
  g->device_trace_ = GpuDeviceTracePipelines::create(dev, error);
  if (g->device_trace_ == nullptr) return nullptr;

  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = device.queue_family_index;
  VkResult r = vkCreateCommandPool(dev, &pool_info, nullptr, &g->command_pool_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateCommandPool", r), nullptr;
  auto cb_info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cb_info.commandPool = g->command_pool_;
  cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_info.commandBufferCount = 1;
  r = vkAllocateCommandBuffers(dev, &cb_info, &g->command_buffer_);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateCommandBuffers", r), nullptr;
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  r = vkCreateFence(dev, &fence_info, nullptr, &g->fence_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateFence", r), nullptr;
  return g;
}

GpuReconstructor::~GpuReconstructor() {
  VkDevice dev = device_.device;
  if (dev == VK_NULL_HANDLE) return;
  if (fence_ != VK_NULL_HANDLE) vkDestroyFence(dev, fence_, nullptr);
  if (command_pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(dev, command_pool_, nullptr);
  for (VkPipeline p : {scatter_, gather_, temporal_, encode_})
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(dev, p, nullptr);
  if (pipeline_layout_ != VK_NULL_HANDLE) vkDestroyPipelineLayout(dev, pipeline_layout_, nullptr);
  if (set_layout_ != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
}

bool GpuReconstructor::create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible, VkBuffer* buffer,
                                     VkDeviceMemory* memory, void** mapped, std::string* error) {
  return create_bound_buffer(device_.device, memory_properties_, std::max<VkDeviceSize>(size, 16), usage,
                             buffer_memory_flags(host_visible), buffer, memory, mapped, error);
}

bool GpuReconstructor::submit_and_wait(const std::function<bool(VkCommandBuffer)>& record, std::string* error) {
  VkDevice dev = device_.device;
  VkResult r = vkResetCommandBuffer(command_buffer_, 0);
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (r == VK_SUCCESS) r = vkBeginCommandBuffer(command_buffer_, &begin);
  if (r != VK_SUCCESS) return *error = vk_error("vkBeginCommandBuffer", r), false;
  const bool recorded = record(command_buffer_);
  r = vkEndCommandBuffer(command_buffer_);
  if (!recorded) return false;
  if (r == VK_SUCCESS) r = vkResetFences(dev, 1, &fence_);
  auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &command_buffer_;
  if (r == VK_SUCCESS) r = vkQueueSubmit(queue_, 1, &submit, fence_);
  if (r == VK_SUCCESS) r = vkWaitForFences(dev, 1, &fence_, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS) return *error = vk_error("GPU submission", r), false;
  return true;
}

std::shared_ptr<GpuTables> GpuReconstructor::upload_tables(std::shared_ptr<const foveation::ViewTables> tables,
                                                           std::string* error, std::size_t max_chunk_bytes) {
  std::shared_ptr<GpuTables> g(new GpuTables());
  g->device_ = device_.device;
  g->tables_ = std::move(tables);
  const std::size_t limit = std::size_t(max_chunk_bytes_);
  if (!pack_gpu_tables(*g->tables_, max_chunk_bytes > 0 ? std::min(max_chunk_bytes, limit) : limit, &g->pack_, error)) {
    return nullptr;
  }
  for (GpuTableChunk& chunk : g->pack_.chunks) {
    const VkDeviceSize bytes = chunk.words.size() * 4;
    VkBuffer buffer = VK_NULL_HANDLE, staging = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE, staging_memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
    bool ok = create_buffer(bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
                            &buffer, &memory, nullptr, error);
    g->buffers_.push_back(buffer);
    g->memory_.push_back(memory);
    // Through a staging buffer: device-local memory need not be host-visible (discrete GPUs).
    ok = ok && create_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, &staging, &staging_memory, &mapped, error);
    if (ok) {
      std::memcpy(mapped, chunk.words.data(), bytes);
      ok = submit_and_wait(
          [&](VkCommandBuffer cb) {
            const VkBufferCopy copy{0, 0, bytes};
            vkCmdCopyBuffer(cb, staging, buffer, 1, &copy);
            memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute,
                           VK_ACCESS_SHADER_READ_BIT);
            return true;
          },
          error);
    }
    if (staging != VK_NULL_HANDLE) vkDestroyBuffer(device_.device, staging, nullptr);
    if (staging_memory != VK_NULL_HANDLE) vkFreeMemory(device_.device, staging_memory, nullptr);
    if (!ok) return nullptr;
    g->bytes_ += bytes;
    chunk.words = {};  // on the device now
  }
  return g;
}

GpuTables::~GpuTables() {
  for (VkBuffer b : buffers_)
    if (b != VK_NULL_HANDLE) vkDestroyBuffer(device_, b, nullptr);
  for (VkDeviceMemory m : memory_)
    if (m != VK_NULL_HANDLE) vkFreeMemory(device_, m, nullptr);
}

std::unique_ptr<GpuEye> GpuReconstructor::create_eye(uint32_t width_px, uint32_t height_px, std::string* error) {
  std::unique_ptr<GpuEye> e(new GpuEye());
  e->owner_ = this;
  e->device_ = device_.device;
  e->width_px_ = width_px;
  e->height_px_ = height_px;
  const VkDeviceSize pixels = VkDeviceSize{width_px} * height_px;
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  auto make = [&](GpuEye::Buffer& b, VkDeviceSize size, VkBufferUsageFlags usage) {
    b.size = size;
    return create_buffer(size, usage, false, &b.buffer, &b.memory, nullptr, error);
  };
  if (!make(e->current_, pixels * 16, storage) || !make(e->history_[0], pixels * 16, storage) ||
      !make(e->history_[1], pixels * 16, storage) ||
      !make(e->encoded_, pixels * 4, storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT)) {
    return nullptr;
  }
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * (uint32_t(kMaxGpuChunks) + kBindings - 1)};
  auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = 2;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  VkResult r = vkCreateDescriptorPool(device_.device, &pool_info, nullptr, &e->pool_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateDescriptorPool", r), nullptr;
  const VkDescriptorSetLayout layouts[2] = {set_layout_, set_layout_};
  auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = e->pool_;
  alloc.descriptorSetCount = 2;
  alloc.pSetLayouts = layouts;
  r = vkAllocateDescriptorSets(device_.device, &alloc, e->sets_);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateDescriptorSets", r), nullptr;
  if (timestamps_) {
    auto query_info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
    query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query_info.queryCount = kQueries;
    r = vkCreateQueryPool(device_.device, &query_info, nullptr, &e->queries_);
    if (r != VK_SUCCESS) return *error = vk_error("vkCreateQueryPool", r), nullptr;
  }
  return e;
}

// ---- GpuEye -------------------------------------------------------------------

void GpuEye::destroy(Buffer& b) {
  destroy_buffer(device_, &b);
}

GpuEye::~GpuEye() {
  if (queries_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_, queries_, nullptr);
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  for (Buffer* b : {&upload_, &colors_, &point_depth_, &current_, &history_[0], &history_[1], &encoded_, &readback_}) {
    destroy(*b);
  }
}

bool GpuEye::ensure_points(std::size_t point_count, std::string* error) {
  if (point_count <= point_capacity_) return true;
  destroy(upload_);
  destroy(colors_);
  destroy(point_depth_);
  point_capacity_ = 0;
  const VkDeviceSize bytes = VkDeviceSize{point_count} * 16;
  upload_.size = bytes + VkDeviceSize{point_count} * 4 + 16;  // entries, then a depth each
  colors_.size = bytes;
  point_depth_.size = VkDeviceSize{point_count} * 4;
  if (!owner_->create_buffer(upload_.size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, &upload_.buffer, &upload_.memory,
                             &upload_.mapped, error) ||
      !owner_->create_buffer(bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
                             &colors_.buffer, &colors_.memory, nullptr, error) ||
      !owner_->create_buffer(point_depth_.size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             false, &point_depth_.buffer, &point_depth_.memory, nullptr, error)) {
    return false;
  }
  point_capacity_ = point_count;
  bound_tables_ = nullptr;  // descriptors name the old buffers
  return true;
}

void GpuEye::update_descriptors() {
  const auto& buffers = bound_tables_->buffers_;
  VkDescriptorBufferInfo chunks[kMaxGpuChunks];
  for (std::size_t i = 0; i < kMaxGpuChunks; ++i) {
    // Unused slots repeat the last chunk: every descriptor of the array is valid.
    chunks[i] = {buffers[std::min(i, buffers.size() - 1)], 0, VK_WHOLE_SIZE};
  }
  for (int s = 0; s < 2; ++s) {
    VkDescriptorBufferInfo info[kMaxGpuChunks + kBindings - 1] = {};
    std::copy(std::begin(chunks), std::end(chunks), info);
    const VkDescriptorBufferInfo rest[kBindings - 1] = {
        {colors_.buffer, 0, VK_WHOLE_SIZE},     {current_.buffer, 0, VK_WHOLE_SIZE},
        {history_[s].buffer, 0, VK_WHOLE_SIZE}, {history_[1 - s].buffer, 0, VK_WHOLE_SIZE},
        {upload_.buffer, 0, VK_WHOLE_SIZE},     {encoded_.buffer, 0, VK_WHOLE_SIZE},
        {point_depth_.buffer, 0, VK_WHOLE_SIZE}};
    std::copy(std::begin(rest), std::end(rest), info + kMaxGpuChunks);
    write_storage_descriptors(device_, sets_[s], info, kDescriptorCounts, kBindings);
  }
}

bool GpuEye::record(VkCommandBuffer cb, const GpuFrame& frame, VkImage image, foveation::Executor& executor,
                    std::string* error) {
  recorded_ = false;
  const GpuTables& tables = *frame.tables;
  const auto& m = frame.mapping;
  if (uint32_t(m.screen_width_px) != width_px_ || uint32_t(m.screen_height_px) != height_px_) {
    return *error = "GPU eye is " + std::to_string(width_px_) + "x" + std::to_string(height_px_) + ", the frame " +
                    std::to_string(m.screen_width_px) + "x" + std::to_string(m.screen_height_px),
           false;
  }
  const std::size_t point_count = tables.view_tables().points.size();
  if (frame.device == nullptr && (frame.colors == nullptr || frame.colors->size() != point_count)) {
    return *error = "GPU frame: point colours do not match the tables", false;
  }
  host_written_ = 0;
  host_read_ = 0;
  std::size_t traced_points = 0;
  for (const auto& run : frame.traced) traced_points += run.size();
  if (traced_points > point_count) return *error = "GPU frame: more traced points than points", false;
  if (!ensure_points(point_count, error)) return false;
  if (bound_tables_ != &tables) {
    bound_tables_ = &tables;
    update_descriptors();
  }

  const VkDescriptorSet set = sets_[parity_];
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->pipeline_layout_, 0, 1, &set, 0, nullptr);
  if (queries_ != VK_NULL_HANDLE) vkCmdResetQueryPool(cb, queries_, 0, kQueries);
  // Last frame's passes read and wrote these buffers (an earlier submission).
  memory_barrier(cb, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 kShaderRW | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT);
  if (!record_reconstruct(cb, frame, executor, error)) return false;  // stages (1-3 on the device and) 4
  if (!record_temporal(cb, frame, set, executor, error)) return false;  // stage 5
  record_encode(cb, frame, image);                                       // stage 6
  parity_ ^= 1;  // this frame's output is the next frame's history
  recorded_ = true;
  return true;
}

void GpuEye::stamp(VkCommandBuffer cb, uint32_t query) const {
  if (queries_ != VK_NULL_HANDLE) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, query);
}

// Stage 4: the traced points' colours and depths up, scattered into their
// slots, and every pixel gathered from them.
bool GpuEye::record_reconstruct(VkCommandBuffer cb, const GpuFrame& frame, foveation::Executor& executor,
                                std::string* error) {
  const GpuTables& tables = *frame.tables;
  const GpuTablePack& pack = tables.pack_;
  const auto& m = frame.mapping;
  const std::size_t point_count = tables.view_tables().points.size();
  // The traced points' colours, run by run into the upload buffer (none for a device trace).
  std::vector<std::size_t> first(frame.traced.size() + 1, 0);
  if (frame.device == nullptr)
    for (std::size_t i = 0; i < frame.traced.size(); ++i) first[i + 1] = first[i] + frame.traced[i].size();
  const std::size_t uploaded = first.back();  // at most point_count (record)
  auto* entries = static_cast<uint32_t*>(upload_.mapped);
  auto* depths = reinterpret_cast<float*>(entries + uploaded * 4);  // shaders/common.glsl Upload
  if (uploaded > 0) {
    const foveation::Rgba* colors = frame.colors->rgba.data();
    const bool has_depth = frame.point_depth_m != nullptr && frame.point_depth_m->size() == point_count;
    executor.parallel_for(frame.traced.size(), [&](std::size_t run) {
      uint32_t* e = entries + first[run] * 4;
      float* d = depths + first[run];
      for (uint32_t id : frame.traced[run]) {
        e[0] = id;
        std::memcpy(e + 1, &colors[id], 12);
        *d++ = has_depth ? shader_depth((*frame.point_depth_m)[id]) : kDepthUnknown;
        e += 4;
      }
    });
    host_written_ += uploaded * 20;
  }

  stamp(cb, 0);
  vkCmdFillBuffer(cb, colors_.buffer, 0, VK_WHOLE_SIZE, 0u);  // every point "not traced" (a = 0)
  uint32_t unknown_bits = 0;
  std::memcpy(&unknown_bits, &kDepthUnknown, 4);
  vkCmdFillBuffer(cb, point_depth_.buffer, 0, VK_WHOLE_SIZE, unknown_bits);
  memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
  if (frame.device != nullptr) {  // stages 1-3 on the device, resolved into the slots
    if (device_trace_ == nullptr) device_trace_ = std::make_unique<GpuDeviceTrace>(*owner_);
    if (!device_trace_->record(cb, *frame.device, colors_.buffer, point_depth_.buffer, error)) return false;
    host_written_ += device_trace_->host_bytes_written();
    const VkDescriptorSet set = sets_[parity_];
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->pipeline_layout_, 0, 1, &set, 0, nullptr);
  } else if (uploaded > 0) {
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->scatter_);
    const ScatterPush push{uint32_t(uploaded), uint32_t(point_count)};
    vkCmdPushConstants(cb, owner_->pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    vkCmdDispatch(cb, groups(uint32_t(uploaded), 64), 1, 1);
  }
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  stamp(cb, 1);

  GatherPush g{};
  g.screen_px[0] = m.screen_width_px;
  g.screen_px[1] = m.screen_height_px;
  g.canvas_offset_px[0] = m.canvas_from_screen_x_px;
  g.canvas_offset_px[1] = m.canvas_from_screen_y_px;
  g.canvas_px[0] = pack.canvas_width_px;
  g.canvas_px[1] = pack.canvas_height_px;
  const int tile = foveation::kGatherTilePx;
  g.first_tile[0] = m.canvas_from_screen_x_px / tile;
  g.first_tile[1] = m.canvas_from_screen_y_px / tile;
  const int last_tile_x = (m.canvas_from_screen_x_px + m.screen_width_px - 1) / tile;
  const int last_tile_y = (m.canvas_from_screen_y_px + m.screen_height_px - 1) / tile;
  g.k = pack.k;
  g.neighbor_k = pack.neighbor_k;
  g.flags = (pack.weighted ? kWeighted : 0u) | (pack.f16 ? kF16 : 0u) | (pack.rbf ? kRbf : 0u);
  if (pack.rbf && frame.rbf_clamp == foveation::RbfClamp::taps) g.flags |= kClampTaps;
  if (pack.rbf && frame.rbf_clamp == foveation::RbfClamp::block) g.flags |= kClampBlock;
  g.chunk_count = uint32_t(pack.chunks.size());
  for (int c = 0; c < 3; ++c) g.fallback_rgb[c] = frame.fallback_rgb[std::size_t(c)];
  for (std::size_t c = 0; c < pack.chunks.size(); ++c) g.chunk_first_row[c] = pack.chunks[c].first_row;
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->gather_);
  vkCmdPushConstants(cb, owner_->pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof g, &g);
  vkCmdDispatch(cb, uint32_t(last_tile_x - g.first_tile[0] + 1), uint32_t(last_tile_y - g.first_tile[1] + 1), 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  stamp(cb, 2);
  return true;
}

// Stage 5: the image history (blend, reprojected from history_view), or the
// render cache writing its frame over the gather (the temporal pass then copies it).
bool GpuEye::record_temporal(VkCommandBuffer cb, const GpuFrame& frame, VkDescriptorSet set,
                             foveation::Executor& executor, std::string* error) {
  if (frame.ray_cache) {  // the render cache writes its frame over the gather; the temporal pass then copies it
    if (ray_cache_ == nullptr) {
      ray_cache_ = std::make_unique<GpuRayCache>(*owner_->ray_cache_, owner_->memory_properties_, current_.buffer,
                                                 width_px_, height_px_, owner_->max_chunk_bytes_);
    }
    if (!ray_cache_->record(cb, *frame.ray_cache, frame.view, executor, error)) return false;
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->pipeline_layout_, 0, 1, &set, 0, nullptr);
  }
  TemporalPush t{};
  t.size_px[0] = int32_t(width_px_);
  t.size_px[1] = int32_t(height_px_);
  t.current_weight = frame.blend.current_weight;
  t.variance_gamma = frame.blend.variance_gamma;
  t.constraint = frame.blend.constraint == foveation::HistoryClip::variance_clip ? 1u : 0u;
  t.reset = frame.temporal_reset || frame.ray_cache ? 1u : 0u;
  t.clip_floor = frame.blend.clip_floor;
  if (frame.history_view && !frame.temporal_reset && !frame.ray_cache) {
    // foveation::reproject_history's world-space step, folded into one rigid
    // transform from this view's space to the last view's.
    const foveation::EyePose now = foveation::eye_pose(frame.view), last = foveation::eye_pose(*frame.history_view);
    const glm::quat q = glm::conjugate(last.orientation) * now.orientation;
    const glm::vec3 translation = glm::conjugate(last.orientation) * (now.position_m - last.position_m);
    const foveation::EyeFrustum fv = foveation::eye_frustum(frame.view),
                                fl = foveation::eye_frustum(*frame.history_view);
    t.reproject = frame.blend.history_sampling == foveation::HistorySampling::catmull_rom ? 2u : 1u;
    const float qv[4] = {q.x, q.y, q.z, q.w}, tv[4] = {translation.x, translation.y, translation.z, 0.0f};
    const float tan_view[4] = {fv.tan_left, fv.tan_right, fv.tan_up, fv.tan_down};
    const float tan_last[4] = {fl.tan_left, fl.tan_right, fl.tan_up, fl.tan_down};
    std::memcpy(t.last_from_view_q, qv, sizeof qv);
    std::memcpy(t.last_from_view_t, tv, sizeof tv);
    std::memcpy(t.tan_view, tan_view, sizeof tan_view);
    std::memcpy(t.tan_last, tan_last, sizeof tan_last);
  }
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->temporal_);
  vkCmdPushConstants(cb, owner_->pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof t, &t);
  vkCmdDispatch(cb, groups(width_px_, 8), groups(height_px_, 8), 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  stamp(cb, 3);
  return true;
}

// Stage 6: the display transform and 8-bit (sRGB) encode, and the copy into the swapchain image.
void GpuEye::record_encode(VkCommandBuffer cb, const GpuFrame& frame, VkImage image) {
  const EncodePush e{{int32_t(width_px_), int32_t(height_px_)},
                     frame.srgb ? 1u : 0u,
                     frame.display.exposure,
                     foveation::tone_map_shader_id(frame.display.tone_map)};
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, owner_->encode_);
  vkCmdPushConstants(cb, owner_->pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof e, &e);
  vkCmdDispatch(cb, groups(width_px_, 8), groups(height_px_, 8), 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  if (image != VK_NULL_HANDLE) record_copy_to_swapchain_image(cb, encoded_.buffer, image, width_px_, height_px_);
  stamp(cb, 4);
}

bool GpuEye::stage_times(GpuStageTimes* out) const {
  if (!recorded_ || queries_ == VK_NULL_HANDLE) return false;
  uint64_t t[kQueries] = {};
  if (vkGetQueryPoolResults(device_, queries_, 0, kQueries, sizeof t, t, sizeof(uint64_t), VK_QUERY_RESULT_64_BIT) !=
      VK_SUCCESS) {
    return false;
  }
  host_read_ += sizeof t;
  const double ms = double(owner_->timestamp_period_ns_) * 1e-6;
  auto span = [&](int a) { return float(double(t[a + 1] - t[a]) * ms); };
  *out = GpuStageTimes{span(0), span(1), span(2), span(3)};
  return true;
}

DeviceTraceStatus GpuEye::device_trace_status() const {
  if (device_trace_ == nullptr) return {};
  host_read_ += FOVEART_DEVICE_STATUS_WORDS * 4;
  return device_trace_->status();
}

XrResult GpuEye::device_trace_result() const {
  return device_trace_ != nullptr ? device_trace_->engine_result() : XR_SUCCESS;
}

std::uint64_t GpuEye::host_bytes_written() const { return host_written_; }
std::uint64_t GpuEye::host_bytes_read() const { return host_read_; }

bool GpuEye::read_rgba8(std::vector<std::uint8_t>* out, std::string* error) {
  const VkDeviceSize bytes = VkDeviceSize{width_px_} * height_px_ * 4;
  if (readback_.buffer == VK_NULL_HANDLE) {
    readback_.size = bytes;
    if (!owner_->create_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, &readback_.buffer, &readback_.memory,
                               &readback_.mapped, error)) {
      return false;
    }
  }
  const bool ok = owner_->submit_and_wait(
      [&](VkCommandBuffer cb) {
        memory_barrier(cb, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        const VkBufferCopy copy{0, 0, bytes};
        vkCmdCopyBuffer(cb, encoded_.buffer, readback_.buffer, 1, &copy);
        memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_HOST_READ_BIT);
        return true;
      },
      error);
  if (!ok) return false;
  out->resize(std::size_t(bytes));
  std::memcpy(out->data(), readback_.mapped, std::size_t(bytes));
  return true;
}

}  // namespace foveart::layer
