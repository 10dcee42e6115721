#include "gpu/ray_cache.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "foveation/eye_rays.hpp"
#include "foveation/shader_constants.h"
#include "gpu/shader_depth.hpp"
#include "gpu/shader_interface/ray_cache.h"
#include "shaders/cache_bin.spv.h"
#include "shaders/cache_filter.spv.h"
#include "shaders/cache_rays.spv.h"
#include "shaders/cache_scan.spv.h"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {
namespace {

using shader::CachePush;

// Buffers as ray_cache.glsl binds them, and their element sizes.
enum Binding : uint32_t {
  kCurrent = 0,
  kAnchorsIn,
  kAnchorsOut,
  kNewRays,
  kRayFrame,
  kCells,
  kByCell,
  kPixels,
  kCounter,
  kBindings
};
constexpr uint32_t kDescriptorCounts[kBindings] = {1, 1, 1, 1, 1, 1, 1, 1, 1};  // one buffer each
constexpr VkDeviceSize kAnchorBytes = sizeof(shader::Anchor), kNewRayBytes = sizeof(shader::NewRay),
                       kRayFrameBytes = sizeof(shader::RayFrame), kCellRayBytes = sizeof(shader::CellRay);
constexpr uint32_t kCellPx = FOVEART_RAY_CACHE_CELL_PX;
constexpr uint32_t kScanBlock = FOVEART_RAY_CACHE_SCAN_BLOCK;
constexpr uint32_t kGroupSize = FOVEART_RAY_CACHE_GROUP_SIZE;  // cache_rays / cache_scan / cache_bin
constexpr uint32_t kMaxGroups = 65535;  // the least maxComputeWorkGroupCount[0]; the shaders loop beyond


uint32_t groups_for(std::size_t n) {
  return uint32_t(std::clamp<std::size_t>((n + kGroupSize - 1) / kGroupSize, 1, kMaxGroups));
}

}  // namespace

// ---- RayCachePipelines -----------------------------------------------------

std::unique_ptr<RayCachePipelines> RayCachePipelines::create(VkDevice device, std::string* error) {
  std::unique_ptr<RayCachePipelines> p(new RayCachePipelines());
  p->device_ = device;
  if (!create_storage_pipeline_layout(device, kDescriptorCounts, kBindings, sizeof(CachePush), &p->set_layout_,
                                      &p->layout_, error)) {
    return nullptr;
  }
  const bool ok = create_compute_pipeline(device, p->layout_, foveart_cache_rays_spv, sizeof foveart_cache_rays_spv,
                                          &p->rays_, error) &&
                  create_compute_pipeline(device, p->layout_, foveart_cache_scan_spv, sizeof foveart_cache_scan_spv,
                                          &p->scan_, error) &&
                  create_compute_pipeline(device, p->layout_, foveart_cache_bin_spv, sizeof foveart_cache_bin_spv,
                                          &p->bin_, error) &&
                  create_compute_pipeline(device, p->layout_, foveart_cache_filter_spv, sizeof foveart_cache_filter_spv,
                                          &p->filter_, error);
  if (!ok) return nullptr;
  return p;
}

RayCachePipelines::~RayCachePipelines() {
  for (VkPipeline p : {rays_, scan_, bin_, filter_})
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(device_, p, nullptr);
  if (layout_ != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, layout_, nullptr);
  if (set_layout_ != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
}

// ---- RayCache --------------------------------------------------------------

RayCache::RayCache(const Context& context, const RayCachePipelines& pipelines, VkBuffer current,
                   std::uint32_t width_px, std::uint32_t height_px, VkDeviceSize max_buffer_bytes)
    : context_(context),
      pipelines_(pipelines),
      device_(context.vk_device()),
      max_buffer_bytes_(max_buffer_bytes > 0 ? max_buffer_bytes : context.max_storage_buffer_bytes()),
      current_(current),
      width_px_(width_px),
      height_px_(height_px),
      // foveation RayCache::filter_at's grid: one cell before the image, so it holds every ray within reach.
      cells_x_((width_px + 2 * kCellPx - 1) / kCellPx + 1),
      cells_y_((height_px + 2 * kCellPx - 1) / kCellPx + 1) {}

RayCache::~RayCache() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  for (Buffer* b : {&anchors_[0], &anchors_[1], &new_rays_, &ray_frame_, &cells_, &by_cell_, &pixels_, &counter_})
    destroy(*b);
  for (Buffer& b : retired_) destroy(b);
}

bool RayCache::make(Buffer& b, VkDeviceSize size, bool host_visible, std::string* error) {
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  return context_.create_buffer(&b, size, usage, host_visible, error);
}

void RayCache::destroy(Buffer& b) {
  destroy_buffer(device_, &b);
}

std::size_t RayCache::kept_rays() const {
  if (!recorded_ || counter_.mapped == nullptr) return 0;
  std::uint32_t kept = 0;
  std::memcpy(&kept, counter_.mapped, sizeof kept);
  return std::min<std::size_t>(kept, capacity_);
}

bool RayCache::update_descriptors(std::string* error) {
  VkDevice device = device_;
  if (pool_ == VK_NULL_HANDLE) {
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * kBindings};
    auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    pool_info.maxSets = 2;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    VkResult r = vkCreateDescriptorPool(device, &pool_info, nullptr, &pool_);
    if (r != VK_SUCCESS) return *error = vk_error("vkCreateDescriptorPool (render cache)", r), false;
    const VkDescriptorSetLayout layouts[2] = {pipelines_.set_layout(), pipelines_.set_layout()};
    auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
    alloc.descriptorPool = pool_;
    alloc.descriptorSetCount = 2;
    alloc.pSetLayouts = layouts;
    r = vkAllocateDescriptorSets(device, &alloc, sets_);
    if (r != VK_SUCCESS) return *error = vk_error("vkAllocateDescriptorSets (render cache)", r), false;
  }
  for (int s = 0; s < 2; ++s) {
    const VkDescriptorBufferInfo info[kBindings] = {{current_, 0, VK_WHOLE_SIZE},
                                                    {anchors_[s].buffer, 0, VK_WHOLE_SIZE},
                                                    {anchors_[1 - s].buffer, 0, VK_WHOLE_SIZE},
                                                    {new_rays_.buffer, 0, VK_WHOLE_SIZE},
                                                    {ray_frame_.buffer, 0, VK_WHOLE_SIZE},
                                                    {cells_.buffer, 0, VK_WHOLE_SIZE},
                                                    {by_cell_.buffer, 0, VK_WHOLE_SIZE},
                                                    {pixels_.buffer, 0, VK_WHOLE_SIZE},
                                                    {counter_.buffer, 0, VK_WHOLE_SIZE}};
    write_storage_descriptors(device, sets_[s], info, kDescriptorCounts, kBindings);
  }
  return true;
}

bool RayCache::ensure_capacity(VkCommandBuffer cb, std::size_t kept, std::size_t added, std::string* error) {
  const std::size_t max_rays = std::size_t(max_buffer_bytes_ / kAnchorBytes);  // anchors are the largest
  if (kept + added > max_rays) {  // before anything changes: a refused frame leaves the cache as it was
    return *error = "GPU render cache: " + std::to_string(kept + added) + " rays need " +
                    std::to_string((kept + added) * kAnchorBytes) +
                    " bytes in one buffer, more than the device's maxStorageBufferRange (" +
                    std::to_string(max_buffer_bytes_) + ")",
           false;
  }
  for (Buffer& b : retired_) destroy(b);  // the last submission, which used them, has finished
  retired_.clear();
  if (cells_.buffer == VK_NULL_HANDLE) {  // per eye: sized by the image
    const VkDeviceSize cell_count = VkDeviceSize{cells_x_} * cells_y_;
    const VkDeviceSize blocks = (cell_count + kScanBlock - 1) / kScanBlock;
    if (!make(cells_, (cell_count + 1 + blocks) * 4, false, error) ||
        !make(pixels_, VkDeviceSize{width_px_} * height_px_ * 8, true, error) || !make(counter_, 4, true, error)) {
      return false;
    }
    descriptors_stale_ = true;
  }
  // Grown by half again when short, so that a few frames settle the size.
  auto grown = [](std::size_t n) { return (n + n / 2 + 0xFFFF) & ~std::size_t{0xFFFF}; };
  if (added > new_capacity_) {
    destroy(new_rays_);
    new_capacity_ = 0;
    const std::size_t n = grown(added);
    if (!make(new_rays_, VkDeviceSize{n} * kNewRayBytes, true, error)) return false;
    new_capacity_ = n;
    descriptors_stale_ = true;
  }
  if (kept + added > capacity_) {
    const std::size_t n = std::min(grown(kept + added), max_rays);
    Buffer anchors[2], ray_frame, by_cell;
    const bool made =
        make(anchors[0], n * kAnchorBytes, false, error) && make(anchors[1], n * kAnchorBytes, false, error) &&
        make(ray_frame, n * kRayFrameBytes, false, error) && make(by_cell, n * kCellRayBytes, false, error);
    if (!made) {
      for (Buffer* b : {&anchors[0], &anchors[1], &ray_frame, &by_cell}) destroy(*b);
      return false;
    }
    if (kept > 0) {  // the kept rays move into the larger buffer (the fills' barrier in record orders the copy)
      const VkBufferCopy copy{0, 0, VkDeviceSize{kept} * kAnchorBytes};
      vkCmdCopyBuffer(cb, anchors_[parity_].buffer, anchors[parity_].buffer, 1, &copy);
    }
    for (Buffer* b : {&anchors_[0], &anchors_[1], &ray_frame_, &by_cell_}) {
      if (b->buffer != VK_NULL_HANDLE) retired_.push_back(*b);
    }
    anchors_[0] = anchors[0];
    anchors_[1] = anchors[1];
    ray_frame_ = ray_frame;
    by_cell_ = by_cell;
    capacity_ = n;
    descriptors_stale_ = true;
  }
  if (descriptors_stale_ && !update_descriptors(error)) return false;
  descriptors_stale_ = false;
  return true;
}

bool RayCache::record(VkCommandBuffer cb, const RayCacheFrame& frame, const FoveartEyeView& view,
                         foveation::Executor& executor, std::string* error) {
  const std::size_t pixels = std::size_t(width_px_) * height_px_;
  if (frame.rays == nullptr || frame.pixels == nullptr || frame.pixels->size() != pixels) {
    return *error = "GPU render cache: the frame's rays or pixels do not match the eye", false;
  }
  std::vector<std::size_t> first(frame.rays->size() + 1, 0);
  for (std::size_t c = 0; c < frame.rays->size(); ++c) first[c + 1] = first[c] + (*frame.rays)[c].size();
  const std::size_t added = first.back();
  // The kept rays: the last frame's, read back (its submission has finished), none on a restart.
  const std::size_t kept = frame.restart ? 0 : kept_rays();
  if (!ensure_capacity(cb, kept, added, error)) return false;

  // This frame's rays and pixels into the upload buffers.
  auto* rays = static_cast<float*>(new_rays_.mapped);
  executor.parallel_for(frame.rays->size(), [&](std::size_t c) {
    float* out = rays + first[c] * 8;
    for (const foveation::TracedRay& r : (*frame.rays)[c]) {
      const shader::NewRay ray{{r.sample_px.x, r.sample_px.y, shader_depth(r.depth_m), 0.0f},
                               {r.rgb.x, r.rgb.y, r.rgb.z, 0.0f}};
      std::memcpy(out, &ray, sizeof ray);
      out += sizeof ray / sizeof(float);
    }
  });
  auto* pixel_out = static_cast<float*>(pixels_.mapped);
  executor.parallel_chunks(pixels, 16384, [&](std::size_t begin, std::size_t end, unsigned) {
    for (std::size_t p = begin; p < end; ++p) {
      const glm::vec2 v = (*frame.pixels)[p];
      pixel_out[2 * p] = v.x;
      pixel_out[2 * p + 1] = std::isfinite(v.y) && v.y >= 0.0f ? v.y : -1.0f;  // < 0: cannot tell
    }
  });

  CachePush push{};
  const foveation::EyePose pose = foveation::eye_pose(view);
  const foveation::EyeFrustum frustum = foveation::eye_frustum(view);
  push.orientation = {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w};
  push.position_m = {pose.position_m.x, pose.position_m.y, pose.position_m.z, 0.0f};
  push.tan_lrud = {frustum.tan_left, frustum.tan_right, frustum.tan_up, frustum.tan_down};
  push.size_px = {int32_t(width_px_), int32_t(height_px_)};
  push.cells_xy = {int32_t(cells_x_), int32_t(cells_y_)};
  push.kept = uint32_t(kept);
  push.added = uint32_t(added);
  push.filter_kind =
      frame.filter == foveation::PixelFilter::box ? FOVEART_RAY_CACHE_FILTER_BOX : FOVEART_RAY_CACHE_FILTER_BSPLINE2;
  push.max_age = frame.max_age_frames;
  push.cell_count = cells_x_ * cells_y_;
  push.capacity = uint32_t(capacity_);
  const std::size_t rays_this_frame = kept + added;
  const uint32_t blocks = (push.cell_count + kScanBlock - 1) / kScanBlock;

  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.layout(), 0, 1, &sets_[parity_], 0, nullptr);
  auto dispatch = [&](VkPipeline pipeline, uint32_t phase, uint32_t x, uint32_t y) {
    push.scan_phase = phase;
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdPushConstants(cb, pipelines_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    vkCmdDispatch(cb, x, y, 1);
    memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  };
  // Every cell empty, nothing kept yet; the earlier frame's passes read and wrote these buffers.
  vkCmdFillBuffer(cb, cells_.buffer, 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cb, counter_.buffer, 0, VK_WHOLE_SIZE, 0u);
  memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
  dispatch(pipelines_.rays(), 0, groups_for(rays_this_frame), 1);
  dispatch(pipelines_.scan(), FOVEART_SCAN_BLOCKS, blocks, 1);
  dispatch(pipelines_.scan(), FOVEART_SCAN_BLOCK_SUMS, 1, 1);
  dispatch(pipelines_.scan(), FOVEART_SCAN_ADD_BLOCK_SUMS, groups_for(push.cell_count), 1);
  dispatch(pipelines_.bin(), 0, groups_for(rays_this_frame), 1);
  dispatch(pipelines_.filter(), 0, (width_px_ + 7) / 8, (height_px_ + 7) / 8);
  // The kept count, for the next frame's record.
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  parity_ ^= 1;  // the kept rays are in the other buffer now
  recorded_ = true;
  return true;
}

}  // namespace foveart::gpu
