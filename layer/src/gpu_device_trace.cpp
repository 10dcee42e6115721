#include "gpu_device_trace.hpp"

#include <algorithm>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <vector>

#include "foveation/eye_rays.hpp"
#include "foveation/shader_constants.h"
#include "gpu_reconstruction.hpp"
#include "vk_util.hpp"
#include "shaders/device_resolve.spv.h"
#include "shaders/device_rays.spv.h"

namespace foveart::layer {
namespace {

// Push constants as shaders/device_rays.comp declares them (std430).
struct RaysPush {
  float tan_lrud[4];
  float orientation[4];
  float position_m[4];
  int32_t screen_px[2];
  float canvas_from_screen_px[2];
  float margin_px;
  uint32_t rays_per_point;
  uint32_t point_count;
  uint32_t flags;
  uint32_t seed[2];
};
static_assert(sizeof(RaysPush) == 88, "shaders/device_rays.comp push constants");
constexpr uint32_t kBspline2 = 1u, kCountsMode = 2u;

struct ResolvePush {
  uint32_t rays_per_point;
  uint32_t point_count;
};

constexpr uint32_t kRaysBindings = 4;     // points, rays, point index, control
constexpr uint32_t kResolveBindings = 6;  // ray colours, point index, control, status, colours, point depth
constexpr uint32_t kOnes[kResolveBindings] = {1, 1, 1, 1, 1, 1};
constexpr uint32_t kNaNBits = 0x7FC00000u;
constexpr VkDeviceSize kRayBytes = 32, kColorBytes = 16;

uint32_t groups(std::size_t n, uint32_t size) { return uint32_t((n + size - 1) / size); }

// The ray shader's push constants for this frame's view, screen and points.
RaysPush rays_push(const DeviceTraceFrame& frame) {
  const foveation::EyeFrustum f = foveation::eye_frustum(frame.view);
  const foveation::EyePose pose = foveation::eye_pose(frame.view);
  RaysPush push{};
  const float tan_lrud[4] = {f.tan_left, f.tan_right, f.tan_up, f.tan_down};
  const float orientation[4] = {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w};
  const float position[4] = {pose.position_m.x, pose.position_m.y, pose.position_m.z, 0.0f};
  std::memcpy(push.tan_lrud, tan_lrud, sizeof tan_lrud);
  std::memcpy(push.orientation, orientation, sizeof orientation);
  std::memcpy(push.position_m, position, sizeof position);
  push.screen_px[0] = frame.mapping.screen_width_px;
  push.screen_px[1] = frame.mapping.screen_height_px;
  push.canvas_from_screen_px[0] = float(frame.mapping.canvas_from_screen_x_px);
  push.canvas_from_screen_px[1] = float(frame.mapping.canvas_from_screen_y_px);
  push.margin_px = frame.points->visible_margin_px;
  push.rays_per_point = frame.rays_per_point;
  push.point_count = uint32_t(frame.points->size());
  push.flags = frame.pixel_filter == foveation::PixelFilter::bspline2 ? kBspline2 : 0u;
  push.seed[0] = uint32_t(frame.sample_seed);
  push.seed[1] = uint32_t(frame.sample_seed >> 32);
  return push;
}

}  // namespace

std::unique_ptr<GpuDeviceTracePipelines> GpuDeviceTracePipelines::create(VkDevice device, std::string* error) {
  std::unique_ptr<GpuDeviceTracePipelines> p(new GpuDeviceTracePipelines());
  p->device_ = device;
  if (!create_storage_pipeline_layout(device, kOnes, kRaysBindings, sizeof(RaysPush), &p->rays_set_layout_,
                                      &p->rays_layout_, error) ||
      !create_storage_pipeline_layout(device, kOnes, kResolveBindings, sizeof(ResolvePush), &p->resolve_set_layout_,
                                      &p->resolve_layout_, error) ||
      !create_compute_pipeline(device, p->rays_layout_, foveart_device_rays_spv, sizeof foveart_device_rays_spv,
                               &p->rays_, error) ||
      !create_compute_pipeline(device, p->resolve_layout_, foveart_device_resolve_spv,
                               sizeof foveart_device_resolve_spv, &p->resolve_, error)) {
    return nullptr;
  }
  return p;
}

GpuDeviceTracePipelines::~GpuDeviceTracePipelines() {
  for (VkPipeline pipeline : {rays_, resolve_})
    if (pipeline != VK_NULL_HANDLE) vkDestroyPipeline(device_, pipeline, nullptr);
  for (VkPipelineLayout layout : {rays_layout_, resolve_layout_})
    if (layout != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, layout, nullptr);
  for (VkDescriptorSetLayout layout : {rays_set_layout_, resolve_set_layout_})
    if (layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, layout, nullptr);
}

GpuDeviceTrace::GpuDeviceTrace(GpuReconstructor& owner) : owner_(owner), device_(owner.device().device) {}

GpuDeviceTrace::~GpuDeviceTrace() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  for (BoundBuffer* b : {&points_, &staging_, &rays_, &point_index_, &ray_colors_, &control_, &status_})
    destroy_buffer(device_, b);
}

bool GpuDeviceTrace::ensure_buffers(const foveation::PointSet& points, std::uint32_t rays_per_point,
                                    std::string* error) {
  const GpuDeviceTracePipelines& pipelines = *owner_.device_trace_;
  if (pool_ == VK_NULL_HANDLE) {
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kRaysBindings + kResolveBindings};
    auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    pool_info.maxSets = 2;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    VkResult r = vkCreateDescriptorPool(device_, &pool_info, nullptr, &pool_);
    if (r != VK_SUCCESS) return *error = vk_error("vkCreateDescriptorPool", r), false;
    const VkDescriptorSetLayout layouts[2] = {pipelines.rays_set_layout_, pipelines.resolve_set_layout_};
    VkDescriptorSet sets[2] = {};
    auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
    alloc.descriptorPool = pool_;
    alloc.descriptorSetCount = 2;
    alloc.pSetLayouts = layouts;
    r = vkAllocateDescriptorSets(device_, &alloc, sets);
    if (r != VK_SUCCESS) return *error = vk_error("vkAllocateDescriptorSets", r), false;
    rays_set_ = sets[0];
    resolve_set_ = sets[1];
  }
  const auto transfer = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const auto storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  const auto source = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;  // the engine may copy what it reads
  if (control_.buffer == VK_NULL_HANDLE) {
    control_.size = FOVEART_DEVICE_CONTROL_WORDS * 4;
    status_.size = FOVEART_DEVICE_STATUS_WORDS * 4;
    if (!owner_.create_buffer(control_.size, storage | transfer | source | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, false,
                              &control_.buffer, &control_.memory, nullptr, error) ||
        !owner_.create_buffer(status_.size, storage | transfer, true, &status_.buffer, &status_.memory,
                              &status_.mapped, error)) {
      return false;
    }
    descriptors_stale_ = true;
  }
  if (uploaded_points_ != &points) {  // the set's points, once per table set: canvas x, y, radius, pixel grid
    for (BoundBuffer* b : {&points_, &staging_}) destroy_buffer(device_, b);
    uploaded_points_ = nullptr;
    const VkDeviceSize bytes = std::max<VkDeviceSize>(points.size() * 16, 16);
    points_.size = staging_.size = bytes;
    if (!owner_.create_buffer(bytes, storage | transfer, false, &points_.buffer, &points_.memory, nullptr, error) ||
        !owner_.create_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, &staging_.buffer, &staging_.memory,
                              &staging_.mapped, error)) {
      return false;
    }
    auto* packed = static_cast<float*>(staging_.mapped);
    for (std::size_t i = 0; i < points.size(); ++i) {
      packed[4 * i] = points.position_px[i].x;
      packed[4 * i + 1] = points.position_px[i].y;
      packed[4 * i + 2] = points.radius_px[i];
      packed[4 * i + 3] = points.on_pixel_grid(i) ? 1.0f : 0.0f;
    }
    staged_bytes_ = points.size() * 16;
    uploaded_points_ = &points;
    descriptors_stale_ = true;
  }
  const std::size_t rays = points.size() * rays_per_point;
  if (rays > UINT32_MAX / 2) return *error = "device trace: more than 2^31 rays a frame", false;
  if (rays > ray_capacity_ || rays_.buffer == VK_NULL_HANDLE) {
    for (BoundBuffer* b : {&rays_, &point_index_, &ray_colors_}) destroy_buffer(device_, b);
    ray_capacity_ = 0;
    const VkDeviceSize n = std::max<VkDeviceSize>(rays, 1);
    rays_.size = n * kRayBytes;
    point_index_.size = n * 4;
    ray_colors_.size = n * kColorBytes;
    if (!owner_.create_buffer(rays_.size, storage | source, false, &rays_.buffer, &rays_.memory, nullptr, error) ||
        !owner_.create_buffer(point_index_.size, storage | source, false, &point_index_.buffer, &point_index_.memory,
                              nullptr, error) ||
        !owner_.create_buffer(ray_colors_.size, storage | transfer | source, false, &ray_colors_.buffer,
                              &ray_colors_.memory, nullptr, error)) {
      return false;
    }
    ray_capacity_ = uint32_t(n);
    descriptors_stale_ = true;
  }
  return true;
}

void GpuDeviceTrace::update_descriptors(VkBuffer colors, VkBuffer point_depth) {
  const VkDescriptorBufferInfo rays[kRaysBindings] = {{points_.buffer, 0, VK_WHOLE_SIZE},
                                                      {rays_.buffer, 0, VK_WHOLE_SIZE},
                                                      {point_index_.buffer, 0, VK_WHOLE_SIZE},
                                                      {control_.buffer, 0, VK_WHOLE_SIZE}};
  write_storage_descriptors(device_, rays_set_, rays, kOnes, kRaysBindings);
  const VkDescriptorBufferInfo resolve[kResolveBindings] = {
      {ray_colors_.buffer, 0, VK_WHOLE_SIZE}, {point_index_.buffer, 0, VK_WHOLE_SIZE},
      {control_.buffer, 0, VK_WHOLE_SIZE},    {status_.buffer, 0, VK_WHOLE_SIZE},
      {colors, 0, VK_WHOLE_SIZE},             {point_depth, 0, VK_WHOLE_SIZE}};
  write_storage_descriptors(device_, resolve_set_, resolve, kOnes, kResolveBindings);
  bound_colors_ = colors;
  bound_point_depth_ = point_depth;
  descriptors_stale_ = false;
}

bool GpuDeviceTrace::record(VkCommandBuffer cb, const DeviceTraceFrame& frame, VkBuffer colors, VkBuffer point_depth,
                            std::string* error) {
  engine_result_ = XR_SUCCESS;
  if (frame.engine.trace == nullptr || frame.points == nullptr || frame.rays_per_point < 1) {
    return *error = "device trace: no engine, points or rays", false;
  }
  const foveation::PointSet& points = *frame.points;
  if (!ensure_buffers(points, frame.rays_per_point, error)) return false;
  if (descriptors_stale_ || bound_colors_ != colors || bound_point_depth_ != point_depth)
    update_descriptors(colors, point_depth);

  uploaded_bytes_ = 0;
  if (staged_bytes_ > 0) {  // new points: copied in this frame's commands (the staging buffer lives on)
    const VkBufferCopy copy{0, 0, staged_bytes_};
    vkCmdCopyBuffer(cb, staging_.buffer, points_.buffer, 1, &copy);
    uploaded_bytes_ = staged_bytes_;  // staged_bytes_ stays until the frame is recorded in full
  }
  record_rays(cb, frame);
  if (!record_engine_trace(cb, frame, error)) return false;
  staged_bytes_ = 0;  // the points' copy is in a frame that will be submitted
  record_resolve(cb, frame);
  return true;
}

// Stages 1-2: counters cleared, every ray colour NaN (unwritten is invalid), the rays made.
void GpuDeviceTrace::record_rays(VkCommandBuffer cb, const DeviceTraceFrame& frame) {
  const GpuDeviceTracePipelines& pipelines = *owner_.device_trace_;
  const foveation::PointSet& points = *frame.points;
  vkCmdFillBuffer(cb, control_.buffer, 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cb, status_.buffer, 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cb, ray_colors_.buffer, 0, VK_WHOLE_SIZE, kNaNBits);
  memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
  RaysPush push = rays_push(frame);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.rays_);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.rays_layout_, 0, 1, &rays_set_, 0, nullptr);
  vkCmdPushConstants(cb, pipelines.rays_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
  if (!points.position_px.empty()) vkCmdDispatch(cb, groups(points.size(), 64), 1, 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  push.flags |= kCountsMode;
  vkCmdPushConstants(cb, pipelines.rays_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
  vkCmdDispatch(cb, 1, 1, 1);
  // The rays, counts and NaN-filled colours for whatever the engine reads or
  // writes them with (shaders of any kind, copies, indirect commands).
  memory_barrier(cb, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
}

// Stage 3: the engine's trace, recorded by the engine into `cb`.
bool GpuDeviceTrace::record_engine_trace(VkCommandBuffer cb, const DeviceTraceFrame& frame, std::string* error) {
  XrFoveatedDeviceRayBatchFOVEART batch{};
  batch.type = XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART;
  batch.frameIndex = frame.frame_index;
  batch.view = &frame.view;
  batch.rayCapacity = ray_capacity_;
  batch.raysPerPoint = frame.rays_per_point;
  batch.rayCount = {control_.buffer, 0, sizeof(FoveartDeviceRayCount)};
  batch.rays = {rays_.buffer, 0, rays_.size};
  batch.pointIndex = {point_index_.buffer, 0, point_index_.size};
  batch.colors = {ray_colors_.buffer, 0, ray_colors_.size};
  batch.commandBuffer = cb;
  engine_result_ = frame.engine.trace(frame.engine.user_data, &batch);
  if (XR_FAILED(engine_result_)) return *error = "the device trace returned " + std::to_string(engine_result_), false;
  memory_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                 kCompute | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
  return true;
}

// The colours per point, into the gather's slots.
void GpuDeviceTrace::record_resolve(VkCommandBuffer cb, const DeviceTraceFrame& frame) {
  const GpuDeviceTracePipelines& pipelines = *owner_.device_trace_;
  const ResolvePush resolve{frame.rays_per_point, uint32_t(frame.points->size())};
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.resolve_);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.resolve_layout_, 0, 1, &resolve_set_, 0,
                          nullptr);
  vkCmdPushConstants(cb, pipelines.resolve_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof resolve, &resolve);
  vkCmdDispatchIndirect(cb, control_.buffer, FOVEART_DEVICE_RESOLVE_DISPATCH * 4);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute | VK_PIPELINE_STAGE_HOST_BIT,
                 kShaderRW | VK_ACCESS_HOST_READ_BIT);
}

DeviceTraceStatus GpuDeviceTrace::status() const {
  DeviceTraceStatus s;
  if (status_.mapped == nullptr) return s;
  uint32_t words[FOVEART_DEVICE_STATUS_WORDS] = {};
  std::memcpy(words, status_.mapped, sizeof words);
  s.invalid_components = words[FOVEART_DEVICE_STATUS_INVALID_COMPONENTS];
  s.visible_points = words[FOVEART_DEVICE_STATUS_VISIBLE_POINTS];
  return s;
}

}  // namespace foveart::layer
