#include "gpu/device_trace.hpp"

#include <algorithm>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <vector>

#include "foveation/eye_rays.hpp"
#include "foveation/point_rays.hpp"
#include "gpu/shader_interface/device_resolve.h"
#include "gpu/shader_interface/device_rays.h"
#include "gpu/shader_interface/ray_dispatch.h"
#include "gpu/vk_util.hpp"
#include "shaders/device_resolve.spv.h"
#include "shaders/device_rays.spv.h"

namespace foveart::gpu {
namespace {

using shader::DeviceRaysPush;
using shader::DeviceResolvePush;

// points, rays, point index, control, blocks, footprints, levels, tiles, point rays
constexpr uint32_t kRaysBindings = 9;
// ray colours, point index, control, status, colours, point depth, point rays, points, levels, tiles
constexpr uint32_t kResolveBindings = 10;
constexpr uint32_t kOnes[kResolveBindings] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
static_assert(FOVEART_DEVICE_FINEST_LEVEL == foveation::PointLevels::kFinest && foveation::PointLevels::kParents == 3 &&
              FOVEART_DEVICE_NO_PARENT == foveation::PointLevels::kNoParent);
// The rays' steps fill one vec4, and the push constants Vulkan's guaranteed 128 bytes.
static_assert(foveation::kRaysContrastSteps == 4 && sizeof(DeviceRaysPush) <= 128);
constexpr uint32_t kNaNBits = 0x7FC00000u;
constexpr VkDeviceSize kRayBytes = sizeof(shader::DeviceRay), kColorBytes = 16;

// Blocks of points of the compaction (device_rays.comp): a workgroup each.
uint32_t point_blocks(std::size_t points) {
  return uint32_t((points + FOVEART_DEVICE_RAYS_BLOCK - 1) / FOVEART_DEVICE_RAYS_BLOCK);
}
// The compaction's words per block (device_rays.comp's block_first): its rays, traced and thinned points.
constexpr VkDeviceSize kBlockWords = 3;

// device_resolve.comp's workgroups over n tiles.
uint32_t resolve_groups(std::size_t n) {
  return uint32_t((n + FOVEART_DEVICE_RESOLVE_GROUP - 1) / FOVEART_DEVICE_RESOLVE_GROUP);
}

// The ray shader's push constants for this frame's view, screen and points.
DeviceRaysPush rays_push(const DeviceTraceFrame& frame, bool tiles_measured) {
  const foveation::EyeFrustum f = foveation::eye_frustum(frame.view);
  const foveation::EyePose pose = foveation::eye_pose(frame.view);
  DeviceRaysPush push{};
  push.tan_lrud = {f.tan_left, f.tan_right, f.tan_up, f.tan_down};
  push.orientation = {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w};
  push.position_m = {pose.position_m.x, pose.position_m.y, pose.position_m.z, 0.0f};
  push.screen_px = {frame.mapping.screen_width_px, frame.mapping.screen_height_px};
  push.canvas_from_screen_px = {float(frame.mapping.canvas_from_screen_x_px),
                                float(frame.mapping.canvas_from_screen_y_px)};
  push.margin_px = frame.points->visible_margin_px;
  push.rays_per_point = frame.rays_per_point;
  push.point_count = uint32_t(frame.points->size());
  push.flags = frame.pixel_filter == foveation::PixelFilter::bspline2 ? FOVEART_DEVICE_RAYS_BSPLINE2 : 0u;
  push.seed = {uint32_t(frame.sample_seed), uint32_t(frame.sample_seed >> 32)};
  if (frame.density_on()) {
    push.flags |= (frame.density.thins() ? FOVEART_DEVICE_RAYS_THIN : 0u) |
                  (frame.density.varies_rays() ? FOVEART_DEVICE_RAYS_VARY : 0u) |
                  (tiles_measured ? FOVEART_DEVICE_RAYS_MEASURED : 0u);
    push.full_contrast = frame.density.full_contrast;
    push.rays_contrast = frame.density.rays_contrast;
  }
  const glm::vec2 centre_px = frame.points->centre_px();
  push.canvas_centre_px = {centre_px.x, centre_px.y};
  const foveation::RaysContrastSteps steps = foveation::rays_contrast_steps(
      frame.density.rays_contrast, frame.density.rays_doubling_ecc_deg, frame.points->view_distance_px);
  push.rays_step_distance_sq_px2 = {steps.distance_sq_px2[0], steps.distance_sq_px2[1], steps.distance_sq_px2[2],
                                    steps.distance_sq_px2[3]};
  push.tile_px = uint32_t(std::max(frame.density.tile_px, 1));
  return push;
}

// The resolve's push constants for `pass`.
DeviceResolvePush resolve_push(const DeviceTraceFrame& frame, uint32_t pass) {
  DeviceResolvePush push{};
  push.pass = pass;
  push.flags = frame.density_on() ? FOVEART_DEVICE_RESOLVE_OBSERVE : 0u;
  push.screen_px = {frame.mapping.screen_width_px, frame.mapping.screen_height_px};
  push.canvas_from_screen_px = {float(frame.mapping.canvas_from_screen_x_px),
                                float(frame.mapping.canvas_from_screen_y_px)};
  push.tile_px = uint32_t(std::max(frame.density.tile_px, 1));
  push.exposure = frame.density.exposure;
  push.dark_luminance = frame.density.dark_luminance;
  push.full_contrast = frame.density.full_contrast;
  return push;
}

}  // namespace

std::uint64_t device_tiles(std::uint32_t width_px, std::uint32_t height_px, std::uint32_t tile_px) {
  const auto tiles = [tile_px](std::uint32_t px) { return std::uint64_t((px + tile_px - 1) / tile_px); };
  return tiles(width_px) * tiles(height_px);
}

std::uint64_t device_tile_capacity(std::uint32_t width_px, std::uint32_t height_px) {
  return device_tiles(width_px, height_px, FOVEART_DEVICE_MIN_TILE_PX);
}

std::unique_ptr<DeviceTracePipelines> DeviceTracePipelines::create(VkDevice device, std::string* error) {
  std::unique_ptr<DeviceTracePipelines> p(new DeviceTracePipelines());
  p->device_ = device;
  if (!create_storage_pipeline_layout(device, kOnes, kRaysBindings, sizeof(DeviceRaysPush), &p->rays_set_layout_,
                                      &p->rays_layout_, error) ||
      !create_storage_pipeline_layout(device, kOnes, kResolveBindings, sizeof(DeviceResolvePush), &p->resolve_set_layout_,
                                      &p->resolve_layout_, error) ||
      !create_compute_pipeline(device, p->rays_layout_, foveart_device_rays_spv, sizeof foveart_device_rays_spv,
                               &p->rays_, error) ||
      !create_compute_pipeline(device, p->resolve_layout_, foveart_device_resolve_spv,
                               sizeof foveart_device_resolve_spv, &p->resolve_, error)) {
    return nullptr;
  }
  return p;
}

DeviceTracePipelines::~DeviceTracePipelines() {
  for (VkPipeline pipeline : {rays_, resolve_})
    if (pipeline != VK_NULL_HANDLE) vkDestroyPipeline(device_, pipeline, nullptr);
  for (VkPipelineLayout layout : {rays_layout_, resolve_layout_})
    if (layout != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, layout, nullptr);
  for (VkDescriptorSetLayout layout : {rays_set_layout_, resolve_set_layout_})
    if (layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, layout, nullptr);
}

DeviceTrace::DeviceTrace(const Context& context, const DeviceTracePipelines& pipelines)
    : context_(context), pipelines_(pipelines), device_(context.vk_device()) {}

DeviceTrace::~DeviceTrace() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  for (BoundBuffer* b : {&points_, &staging_, &rays_, &point_index_, &ray_colors_, &control_, &blocks_})
    destroy_buffer(device_, b);
  for (BoundBuffer* b : {&footprints_, &point_rays_, &levels_, &levels_staging_}) destroy_buffer(device_, b);
}

bool DeviceTrace::ensure_buffers(const foveation::PointSet& points, std::uint32_t rays_per_point,
                                    std::string* error) {
  if (pool_ == VK_NULL_HANDLE) {
    const VkDescriptorSetLayout layouts[2] = {pipelines_.rays_set_layout(), pipelines_.resolve_set_layout()};
    VkDescriptorSet sets[2] = {};
    if (!allocate_storage_sets(device_, layouts, 2, kRaysBindings + kResolveBindings, &pool_, sets, error)) return false;
    rays_set_ = sets[0];
    resolve_set_ = sets[1];
  }
  const auto transfer = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const auto storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  const auto source = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;  // the engine may copy what it reads
  const auto address = context_.address_usage();          // where the app enabled bufferDeviceAddress
  if (control_.buffer == VK_NULL_HANDLE) {
    if (!context_.create_buffer(&control_, FOVEART_DEVICE_CONTROL_WORDS * 4,
                                storage | transfer | source | address | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, false,
                                error)) {
      return false;
    }
    descriptors_stale_ = true;
  }
  if (uploaded_points_ != &points) {  // the set's points, once per table set: canvas x, y, radius, grid
    for (BoundBuffer* b : {&points_, &staging_, &blocks_, &point_rays_}) destroy_buffer(device_, b);
    uploaded_points_ = nullptr;
    const VkDeviceSize bytes = std::max<VkDeviceSize>(points.size() * sizeof(shader::DevicePoint), 16);
    if (!context_.create_buffer(&points_, bytes, storage | transfer, false, error) ||
        !context_.create_buffer(&staging_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, error) ||
        !context_.create_buffer(&blocks_, std::max<VkDeviceSize>(point_blocks(points.size()), 1) * kBlockWords * 4,
                                storage, false, error) ||
        !context_.create_buffer(&point_rays_, std::max<size_t>(points.size(), 1) * sizeof(shader::DevicePointRays),
                                storage, false, error)) {
      return false;
    }
    auto* packed = static_cast<shader::DevicePoint*>(staging_.mapped);
    for (std::size_t i = 0; i < points.size(); ++i) {
      packed[i].position_radius_grid = {points.position_px[i].x, points.position_px[i].y, points.radius_px[i],
                                        points.in_exact_fovea(i)  ? 2.0f
                                        : points.on_pixel_grid(i) ? 1.0f
                                                                  : 0.0f};
    }
    staged_bytes_ = points.size() * sizeof(shader::DevicePoint);
    uploaded_points_ = &points;
    descriptors_stale_ = true;
  }
  const std::size_t rays = points.size() * rays_per_point;
  if (rays > FOVEART_DEVICE_MAX_RAYS) return *error = "device trace: more than 2^31 - 1 rays a view", false;
  if (rays > ray_capacity_ || rays_.buffer == VK_NULL_HANDLE) {
    for (BoundBuffer* b : {&rays_, &point_index_, &ray_colors_, &footprints_}) destroy_buffer(device_, b);
    ray_capacity_ = 0;
    const VkDeviceSize n = std::max<VkDeviceSize>(rays, 1);
    if (!context_.create_buffer(&rays_, n * kRayBytes, storage | source | address, false, error) ||
        !context_.create_buffer(&point_index_, n * 4, storage | source | address, false, error) ||
        !context_.create_buffer(&ray_colors_, n * kColorBytes, storage | transfer | source | address, false, error) ||
        !context_.create_buffer(&footprints_, n * 4, storage | source | address, false, error)) {
      return false;
    }
    ray_capacity_ = uint32_t(n);
    descriptors_stale_ = true;
  }
  return true;
}

// The set's levels and parents (content density), once per level set; while off, a placeholder to bind.
bool DeviceTrace::ensure_levels(const foveation::PointLevels* levels, std::string* error) {
  if (levels == nullptr ? levels_.buffer != VK_NULL_HANDLE : levels == uploaded_levels_) return true;
  for (BoundBuffer* b : {&levels_, &levels_staging_}) destroy_buffer(device_, b);
  uploaded_levels_ = nullptr;
  staged_level_bytes_ = 0;
  descriptors_stale_ = true;
  const std::size_t n = levels == nullptr ? 0 : levels->size();
  const VkDeviceSize bytes = std::max<VkDeviceSize>(n * sizeof(shader::DeviceLevel), sizeof(shader::DeviceLevel));
  if (!context_.create_buffer(&levels_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              false, error)) {
    return false;
  }
  if (levels == nullptr) return true;
  if (!context_.create_buffer(&levels_staging_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, error)) return false;
  auto* packed = static_cast<shader::DeviceLevel*>(levels_staging_.mapped);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& parent = levels->parent[i];
    const auto& weight = levels->parent_weight[i];
    packed[i].parents_level = {parent[0], parent[1], parent[2], levels->level[i]};
    packed[i].weights = {weight[0], weight[1], weight[2], 0.0f};
  }
  staged_level_bytes_ = n * sizeof(shader::DeviceLevel);
  uploaded_levels_ = levels;
  return true;
}

void DeviceTrace::update_descriptors(const DeviceTraceTargets& targets) {
  const VkDescriptorBufferInfo rays[kRaysBindings] = {
      {points_.buffer, 0, VK_WHOLE_SIZE},  {rays_.buffer, 0, VK_WHOLE_SIZE},   {point_index_.buffer, 0, VK_WHOLE_SIZE},
      {control_.buffer, 0, VK_WHOLE_SIZE}, {blocks_.buffer, 0, VK_WHOLE_SIZE}, {footprints_.buffer, 0, VK_WHOLE_SIZE},
      {levels_.buffer, 0, VK_WHOLE_SIZE},  {targets.tiles, 0, VK_WHOLE_SIZE},  {point_rays_.buffer, 0, VK_WHOLE_SIZE}};
  write_storage_descriptors(device_, rays_set_, rays, kOnes, kRaysBindings);
  const VkDescriptorBufferInfo resolve[kResolveBindings] = {
      {ray_colors_.buffer, 0, VK_WHOLE_SIZE}, {point_index_.buffer, 0, VK_WHOLE_SIZE},
      {control_.buffer, 0, VK_WHOLE_SIZE},    {targets.status, 0, VK_WHOLE_SIZE},
      {targets.colors, 0, VK_WHOLE_SIZE},     {targets.point_depth, 0, VK_WHOLE_SIZE},
      {point_rays_.buffer, 0, VK_WHOLE_SIZE}, {points_.buffer, 0, VK_WHOLE_SIZE},
      {levels_.buffer, 0, VK_WHOLE_SIZE},     {targets.tiles, 0, VK_WHOLE_SIZE}};
  write_storage_descriptors(device_, resolve_set_, resolve, kOnes, kResolveBindings);
  bound_ = targets;
  descriptors_stale_ = false;
}

bool DeviceTrace::record(VkCommandBuffer cb, const DeviceTraceFrame& frame, const DeviceTraceTargets& targets,
                         std::string* error) {
  if (!frame.engine) return *error = "device trace: no engine", false;
  if (!record_rays(cb, frame, targets, error)) return false;
  if (!record_engine_trace(cb, frame, error)) return false;
  record_resolve(cb, frame);
  return true;
}

bool DeviceTrace::record_rays(VkCommandBuffer cb, const DeviceTraceFrame& frame, const DeviceTraceTargets& targets,
                              std::string* error) {
  if (frame.points == nullptr || frame.rays_per_point < 1) return *error = "device trace: no points or rays", false;
  const foveation::PointSet& points = *frame.points;
  if (frame.density_on() && (frame.levels->size() != points.size() || targets.tiles == VK_NULL_HANDLE ||
                             frame.density.tile_px < int(FOVEART_DEVICE_MIN_TILE_PX))) {
    return *error = "device content density: no levels of the set, no tiles, or tiles under 4 px", false;
  }
  if (!ensure_buffers(points, frame.rays_per_point, error) ||
      !ensure_levels(frame.density_on() ? frame.levels : nullptr, error)) {
    return false;
  }
  if (descriptors_stale_ || !bound_.same_buffers(targets)) update_descriptors(targets);
  bound_ = targets;
  record_uploads(cb);
  record_ray_passes(cb, frame);
  return true;
}

// New points and levels, copied in this frame's commands (the staging buffers live on;
// staged bytes stay until the frame's resolve is recorded).
void DeviceTrace::record_uploads(VkCommandBuffer cb) {
  uploaded_bytes_ = 0;
  if (staged_bytes_ > 0) {
    const VkBufferCopy copy{0, 0, staged_bytes_};
    vkCmdCopyBuffer(cb, staging_.buffer, points_.buffer, 1, &copy);
    uploaded_bytes_ += staged_bytes_;
  }
  if (staged_level_bytes_ > 0) {
    const VkBufferCopy copy{0, 0, staged_level_bytes_};
    vkCmdCopyBuffer(cb, levels_staging_.buffer, levels_.buffer, 1, &copy);
    uploaded_bytes_ += staged_level_bytes_;
  }
}

DeviceRayBatch DeviceTrace::batch(const DeviceTraceFrame& frame, VkCommandBuffer cb) const {
  DeviceRayBatch batch;
  batch.frame_index = frame.frame_index;
  batch.view = &frame.view;
  batch.ray_capacity = ray_capacity_;
  batch.rays_per_point = frame.rays_per_point;
  batch.ray_count = {control_.buffer, 0, FOVEART_DEVICE_RAY_COUNT_WORDS * 4};
  batch.rays = {rays_.buffer, 0, rays_.size};
  batch.point_index = {point_index_.buffer, 0, point_index_.size};
  batch.colors = {ray_colors_.buffer, 0, ray_colors_.size};
  batch.footprints = {footprints_.buffer, 0, footprints_.size};
  batch.addresses = {context_.buffer_address(control_.buffer), context_.buffer_address(rays_.buffer),
                     context_.buffer_address(point_index_.buffer), context_.buffer_address(ray_colors_.buffer),
                     context_.buffer_address(footprints_.buffer)};
  batch.command_buffer = cb;
  return batch;
}

// Stages 1-2: every ray colour NaN (unwritten is invalid), the rays made, the SCAN writing
// every control word (the caller cleared the status with the frame's other targets).
void DeviceTrace::record_ray_passes(VkCommandBuffer cb, const DeviceTraceFrame& frame) {
  const foveation::PointSet& points = *frame.points;
  vkCmdFillBuffer(cb, ray_colors_.buffer, 0, VK_WHOLE_SIZE, kNaNBits);
  memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
  // The visible points compacted in the set's order: counts per block, where each block begins, the rays.
  DeviceRaysPush push = rays_push(frame, bound_.tiles_measured);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.rays());
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.rays_layout(), 0, 1, &rays_set_, 0, nullptr);
  const uint32_t blocks = point_blocks(points.size());
  for (const uint32_t pass : {FOVEART_DEVICE_RAYS_COUNT, FOVEART_DEVICE_RAYS_SCAN, FOVEART_DEVICE_RAYS_WRITE}) {
    push.pass = pass;
    vkCmdPushConstants(cb, pipelines_.rays_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    const uint32_t groups = pass == FOVEART_DEVICE_RAYS_SCAN ? 1 : blocks;
    if (groups > 0) vkCmdDispatch(cb, groups, 1, 1);
    memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  }
  // The rays, counts and NaN-filled colours for whatever the engine reads or
  // writes them with (shaders of any kind, copies, indirect commands).
  memory_barrier(cb, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
}

// Stage 3: the engine's trace, recorded by the engine into `cb`.
bool DeviceTrace::record_engine_trace(VkCommandBuffer cb, const DeviceTraceFrame& frame, std::string* error) {
  if (!frame.engine(batch(frame, cb))) return *error = "the device trace failed", false;
  return true;
}

// The colours per point, into the gather's slots (with content density, each
// traced point's luminance into its tile's range, cleared first: min none, max 0).
void DeviceTrace::record_resolve(VkCommandBuffer cb, const DeviceTraceFrame& frame) {
  // The engine's writes in any stage (in `cb`, or a submission this one waited for), and
  // this frame's earlier writes of the tiles (the eye's first clear) before their fills below.
  memory_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                 kCompute | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
  staged_bytes_ = 0;  // the points' and levels' copies are in a frame that will be submitted
  staged_level_bytes_ = 0;
  if (frame.density_on()) {
    const VkDeviceSize capacity =
        device_tile_capacity(uint32_t(frame.mapping.screen_width_px), uint32_t(frame.mapping.screen_height_px));
    const VkDeviceSize header = FOVEART_DEVICE_TILES_HEADER_WORDS * 4;
    vkCmdFillBuffer(cb, bound_.tiles, header + FOVEART_DEVICE_TILE_MIN * capacity * 4, capacity * 4, 0xFFFFFFFFu);
    vkCmdFillBuffer(cb, bound_.tiles, header + FOVEART_DEVICE_TILE_MAX * capacity * 4, capacity * 4, 0u);
    memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
  }
  // A thread per traced point: device_rays.comp's SCAN wrote the group count.
  bind_resolve(cb, frame, FOVEART_DEVICE_RESOLVE_POINTS);
  vkCmdDispatchIndirect(cb, control_.buffer, FOVEART_DEVICE_RESOLVE_DISPATCH * 4);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute | VK_PIPELINE_STAGE_HOST_BIT,
                 kShaderRW | VK_ACCESS_HOST_READ_BIT);
}

void DeviceTrace::record_fill(VkCommandBuffer cb, const DeviceTraceFrame& frame) {
  if (!frame.density_on() || !frame.density.thins()) return;
  bind_resolve(cb, frame, FOVEART_DEVICE_RESOLVE_FILL);  // a thread per thinned point, likewise
  vkCmdDispatchIndirect(cb, control_.buffer, FOVEART_DEVICE_FILL_DISPATCH * 4);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute | VK_PIPELINE_STAGE_HOST_BIT,
                 kShaderRW | VK_ACCESS_HOST_READ_BIT);
}

void DeviceTrace::record_contrast(VkCommandBuffer cb, const DeviceTraceFrame& frame) {
  if (!frame.density_on()) return;
  const auto tiles = uint32_t(device_tiles(uint32_t(frame.mapping.screen_width_px),
                                           uint32_t(frame.mapping.screen_height_px), uint32_t(frame.density.tile_px)));
  bind_resolve(cb, frame, FOVEART_DEVICE_RESOLVE_CONTRAST);
  vkCmdDispatch(cb, std::max<uint32_t>(1, resolve_groups(tiles)), 1, 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
}

void DeviceTrace::bind_resolve(VkCommandBuffer cb, const DeviceTraceFrame& frame, uint32_t pass) {
  const DeviceResolvePush push = resolve_push(frame, pass);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.resolve());
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.resolve_layout(), 0, 1, &resolve_set_, 0,
                          nullptr);
  vkCmdPushConstants(cb, pipelines_.resolve_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
}

}  // namespace foveart::gpu
