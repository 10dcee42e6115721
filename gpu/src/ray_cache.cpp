#include "gpu/ray_cache.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "foveation/eye_rays.hpp"
#include "foveation/gather_layout.hpp"
#include "foveation/shader_constants.h"
#include "gpu/shader_depth.hpp"
#include "gpu/shader_interface/cache_device_rays.h"
#include "gpu/shader_interface/cache_pixels.h"
#include "gpu/shader_interface/cache_push.h"
#include "gpu/vk_util.hpp"
#include "shaders/cache_bin.spv.h"
#include "shaders/cache_count.spv.h"
#include "shaders/cache_device_rays.spv.h"
#include "shaders/cache_filter.spv.h"
#include "shaders/cache_pixels.spv.h"
#include "shaders/cache_rays.spv.h"
#include "shaders/cache_scan.spv.h"

namespace foveart::gpu {
namespace {

using shader::CacheDeviceRaysPush;
using shader::CachePixelsPush;
using shader::CachePush;

// Buffers as ray_cache.glsl binds them.
enum Binding : uint32_t {
  kCurrent = 0,
  kAnchorsIn,
  kAnchorsOut,
  kNewRays,
  kRayFrame,
  kCells,
  kByCell,
  kPixels,
  kCounts,
  kDeviceControl,
  kDeviceStatus,
  kBindings
};
constexpr uint32_t kOnes[kBindings] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};  // one buffer each
// cache_device_rays.comp: rays, ray colours, point index, control, points, new rays, point farthest, drawn.
constexpr uint32_t kDeviceRaysBindings = 8;
// cache_pixels.comp: the table chunks, point colours, points, point farthest, drawn, pixels.
constexpr uint32_t kPixelsBindings = 6;
constexpr uint32_t kPixelsCounts[kPixelsBindings] = {FOVEART_MAX_TABLE_CHUNKS, 1, 1, 1, 1, 1};
constexpr uint32_t kSetsPerSlot = 4;  // the cache's two (one per anchor parity), device rays, pixels
constexpr VkDeviceSize kAnchorBytes = sizeof(shader::Anchor), kNewRayBytes = sizeof(shader::NewRay),
                       kRayFrameBytes = sizeof(shader::RayFrame), kCellRayBytes = sizeof(shader::CellRay);
constexpr uint32_t kCellPx = FOVEART_RAY_CACHE_CELL_PX;
constexpr uint32_t kScanBlock = FOVEART_RAY_CACHE_SCAN_BLOCK;
constexpr uint32_t kGroupSize = FOVEART_RAY_CACHE_GROUP_SIZE;  // cache_scan's
constexpr uint32_t kMaxGroups = 65535;  // the least maxComputeWorkGroupCount[0]; the shaders loop beyond
constexpr std::size_t kMaxUnlimitedFrames = 65536;  // max_age_frames = 0 keeps at most this many frames' rays

uint32_t groups_for(std::size_t n) {
  return uint32_t(std::clamp<std::size_t>((n + kGroupSize - 1) / kGroupSize, 1, kMaxGroups));
}

// Grown by half again when short, so that a few frames settle the size.
std::size_t grown(std::size_t n) { return (n + n / 2 + 0xFFFF) & ~std::size_t{0xFFFF}; }

// A barrier from the compute writes before it to every compute and indirect read after it.
void compute_barrier(VkCommandBuffer cb) {
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                 kShaderRW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
}

// Chunk c's first tile row, into the uvec4s the push constants hold them in.
void set_first_row(CachePixelsPush& push, std::size_t c, uint32_t row) {
  shader::uvec4& v = push.chunk_first_row[c / 4];
  switch (c % 4) {
    case 0: v.x = row; break;
    case 1: v.y = row; break;
    case 2: v.z = row; break;
    default: v.w = row; break;
  }
}

}  // namespace

// ---- RayCachePipelines -----------------------------------------------------

std::unique_ptr<RayCachePipelines> RayCachePipelines::create(VkDevice device, std::string* error) {
  std::unique_ptr<RayCachePipelines> p(new RayCachePipelines());
  p->device_ = device;
  RayCachePipelines& q = *p;
  auto pipeline = [&](VkPipelineLayout layout, const uint32_t* code, std::size_t bytes, VkPipeline* out) {
    return create_compute_pipeline(device, layout, code, bytes, out, error);
  };
  const bool ok =
      create_storage_pipeline_layout(device, kOnes, kBindings, sizeof(CachePush), &q.set_layout_, &q.layout_, error) &&
      create_storage_pipeline_layout(device, kOnes, kDeviceRaysBindings, sizeof(CacheDeviceRaysPush),
                                     &q.device_rays_set_layout_, &q.device_rays_layout_, error) &&
      create_storage_pipeline_layout(device, kPixelsCounts, kPixelsBindings, sizeof(CachePixelsPush),
                                     &q.pixels_set_layout_, &q.pixels_layout_, error) &&
      pipeline(q.layout_, foveart_cache_rays_spv, sizeof foveart_cache_rays_spv, &q.rays_) &&
      pipeline(q.layout_, foveart_cache_scan_spv, sizeof foveart_cache_scan_spv, &q.scan_) &&
      pipeline(q.layout_, foveart_cache_bin_spv, sizeof foveart_cache_bin_spv, &q.bin_) &&
      pipeline(q.layout_, foveart_cache_filter_spv, sizeof foveart_cache_filter_spv, &q.filter_) &&
      pipeline(q.layout_, foveart_cache_count_spv, sizeof foveart_cache_count_spv, &q.count_) &&
      pipeline(q.device_rays_layout_, foveart_cache_device_rays_spv, sizeof foveart_cache_device_rays_spv,
               &q.device_rays_) &&
      pipeline(q.pixels_layout_, foveart_cache_pixels_spv, sizeof foveart_cache_pixels_spv, &q.pixels_);
  if (!ok) return nullptr;
  return p;
}

RayCachePipelines::~RayCachePipelines() {
  for (VkPipeline p : {rays_, scan_, bin_, filter_, count_, device_rays_, pixels_})
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(device_, p, nullptr);
  for (VkPipelineLayout l : {layout_, device_rays_layout_, pixels_layout_})
    if (l != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, l, nullptr);
  for (VkDescriptorSetLayout l : {set_layout_, device_rays_set_layout_, pixels_set_layout_})
    if (l != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, l, nullptr);
}

// ---- RayCache --------------------------------------------------------------

struct RayCache::Frame {
  CachePush push{};
  std::size_t rays = 0;  // the anchors the frame needs: the kept rays' bound and its new rays
  std::deque<std::size_t> added_bound;  // added_bound_ after this frame
};

RayCache::RayCache(const Context& context, const RayCachePipelines& pipelines, VkBuffer current,
                   std::uint32_t width_px, std::uint32_t height_px, std::uint32_t slots, VkDeviceSize max_buffer_bytes)
    : context_(context),
      pipelines_(pipelines),
      device_(context.vk_device()),
      max_buffer_bytes_(max_buffer_bytes > 0 ? max_buffer_bytes : context.max_storage_buffer_bytes()),
      current_(current),
      width_px_(width_px),
      height_px_(height_px),
      // foveation RayCache::filter_at's grid: one cell before the image, so it holds every ray within reach.
      cells_x_((width_px + 2 * kCellPx - 1) / kCellPx + 1),
      cells_y_((height_px + 2 * kCellPx - 1) / kCellPx + 1),
      slots_(std::max<std::uint32_t>(slots, 1)),
      uploads_(slots_) {}

RayCache::~RayCache() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  for (Buffer* b : {&anchors_[0], &anchors_[1], &ray_frame_, &cells_, &by_cell_, &counts_, &readback_,
                    &device_upload_.new_rays, &device_upload_.pixels, &point_farthest_, &drawn_})
    destroy(*b);
  for (SlotBuffers& u : uploads_) {
    destroy(u.new_rays);
    destroy(u.pixels);
  }
  for (auto& [b, until] : retired_) destroy(b);
}

bool RayCache::make(Buffer& b, VkDeviceSize size, bool host_visible, std::string* error) const {
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
  return context_.create_buffer(&b, size, usage, host_visible, error);
}

void RayCache::destroy(Buffer& b) const { destroy_buffer(device_, &b); }

// A buffer a submission in flight may still read: destroyed once the frames recorded since cover every slot.
void RayCache::retire(Buffer& b) {
  if (b.buffer != VK_NULL_HANDLE) retired_.emplace_back(b, records_ + slots_);
  b = Buffer{};
}

bool RayCache::kept_rays_after_wait(Context& context, std::size_t* kept, std::string* error) {
  *kept = 0;
  if (records_ == 0) return true;
  if (readback_.buffer == VK_NULL_HANDLE && !make(readback_, 16, true, error)) return false;
  const bool ok = context.submit_and_wait(
      [&](VkCommandBuffer cb) {
        memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_TRANSFER_READ_BIT);
        const VkBufferCopy copy{FOVEART_CACHE_KEPT_OUT * 4, 0, 4};
        vkCmdCopyBuffer(cb, counts_.buffer, readback_.buffer, 1, &copy);
        memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_HOST_READ_BIT);
        return true;
      },
      error);
  if (!ok) return false;
  std::uint32_t words = 0;
  std::memcpy(&words, readback_.mapped, sizeof words);
  *kept = words;
  return true;
}

// The frame's bound: the kept rays are at most those the frames since the
// restart added, within the age limit; the age limit shortened where the next
// frame (as many new rays as this one) would not fit the device's range.
bool RayCache::plan_frame(const RayCacheFrame& frame, std::size_t added, Frame* out, std::string* error) {
  const std::size_t max_rays = std::size_t(max_buffer_bytes_ / kAnchorBytes);  // anchors are the largest
  if (added > max_rays) {
    return *error = "GPU render cache: " + std::to_string(added) + " new rays need " +
                    std::to_string(added * kAnchorBytes) +
                    " bytes in one buffer, more than the device's maxStorageBufferRange (" +
                    std::to_string(max_buffer_bytes_) + ")",
           false;
  }
  std::deque<std::size_t>& bound = out->added_bound;
  if (!frame.restart) bound = added_bound_;
  const std::size_t kept_bound = std::accumulate(bound.begin(), bound.end(), std::size_t{0});
  out->rays = std::min(kept_bound + added, max_rays);  // beyond the range (a callback's frame outgrowing
                                                       // the last), cache_count keeps fewer
  bound.push_back(added);
  const std::uint32_t age = frame.max_age_frames;
  const std::size_t frames_kept = age != 0 ? std::size_t(age - 1) : kMaxUnlimitedFrames;
  bool shortened = false;
  while (bound.size() > frames_kept) {
    bound.pop_front();
    shortened = age == 0;
  }
  while (!bound.empty() && std::accumulate(bound.begin(), bound.end(), added) > max_rays) {
    bound.pop_front();
    shortened = true;
  }
  out->push.max_age = shortened ? uint32_t(bound.size() + 1) : age;
  return true;
}

bool RayCache::ensure_fixed(std::string* error) {
  if (cells_.buffer != VK_NULL_HANDLE) return true;
  const VkDeviceSize cell_count = VkDeviceSize{cells_x_} * cells_y_;
  const VkDeviceSize blocks = (cell_count + kScanBlock - 1) / kScanBlock;
  const VkDeviceSize pixels = VkDeviceSize{width_px_} * height_px_;
  if (!make(cells_, (cell_count + 1 + blocks) * 4, false, error) ||
      !make(counts_, FOVEART_CACHE_COUNT_WORDS * 4, false, error) || !make(drawn_, pixels * 4, false, error)) {
    return false;
  }
  for (SlotBuffers& u : uploads_)
    if (!make(u.pixels, pixels * 8, true, error)) return false;
  return make(device_upload_.pixels, pixels * 8, false, error);
}

bool RayCache::grow_anchors(VkCommandBuffer cb, std::size_t rays, std::string* error) {
  const std::size_t max_rays = std::size_t(max_buffer_bytes_ / kAnchorBytes);
  const std::size_t n = std::min(grown(rays), max_rays);
  Buffer anchors[2], ray_frame, by_cell;
  const bool made = make(anchors[0], n * kAnchorBytes, false, error) &&
                    make(anchors[1], n * kAnchorBytes, false, error) &&
                    make(ray_frame, n * kRayFrameBytes, false, error) && make(by_cell, n * kCellRayBytes, false, error);
  if (!made) {
    for (Buffer* b : {&anchors[0], &anchors[1], &ray_frame, &by_cell}) destroy(*b);
    return false;
  }
  if (capacity_ > 0) {  // the kept rays move into the larger buffer (the fills' barrier in record orders the copy)
    const VkBufferCopy copy{0, 0, VkDeviceSize{capacity_} * kAnchorBytes};
    vkCmdCopyBuffer(cb, anchors_[parity_].buffer, anchors[parity_].buffer, 1, &copy);
  }
  for (Buffer* b : {&anchors_[0], &anchors_[1], &ray_frame_, &by_cell_}) retire(*b);
  anchors_[0] = anchors[0];
  anchors_[1] = anchors[1];
  ray_frame_ = ray_frame;
  by_cell_ = by_cell;
  capacity_ = n;
  return true;
}

bool RayCache::ensure_capacity(VkCommandBuffer cb, std::size_t rays, std::size_t added, SlotBuffers& upload,
                               bool host_visible, std::string* error) {
  std::erase_if(retired_, [&](auto& r) {  // every submission that may read them has finished
    if (r.second > records_) return false;
    destroy(r.first);
    return true;
  });
  if (!ensure_fixed(error)) return false;
  if (added > upload.new_capacity || upload.new_rays.buffer == VK_NULL_HANDLE) {
    retire(upload.new_rays);
    upload.new_capacity = 0;
    const std::size_t n = grown(std::max<std::size_t>(added, 1));
    if (!make(upload.new_rays, VkDeviceSize{n} * kNewRayBytes, host_visible, error)) return false;
    upload.new_capacity = n;
  }
  return rays <= capacity_ || grow_anchors(cb, rays, error);
}

// This frame's rays and pixels into the slot's upload buffers.
void RayCache::write_upload(const RayCacheFrame& frame, SlotBuffers& upload, foveation::Executor& executor) const {
  std::vector<std::size_t> first(frame.rays->size() + 1, 0);
  for (std::size_t c = 0; c < frame.rays->size(); ++c) first[c + 1] = first[c] + (*frame.rays)[c].size();
  auto* rays = static_cast<float*>(upload.new_rays.mapped);
  executor.parallel_for(frame.rays->size(), [&](std::size_t c) {
    float* out = rays + first[c] * 8;
    for (const foveation::TracedRay& r : (*frame.rays)[c]) {
      const shader::NewRay ray{{r.sample_px.x, r.sample_px.y, shader_depth(r.depth_m), 0.0f},
                               {r.rgb.x, r.rgb.y, r.rgb.z, 0.0f}};
      std::memcpy(out, &ray, sizeof ray);
      out += sizeof ray / sizeof(float);
    }
  });
  auto* pixel_out = static_cast<float*>(upload.pixels.mapped);
  const std::size_t pixels = std::size_t(width_px_) * height_px_;
  executor.parallel_chunks(pixels, 16384, [&](std::size_t begin, std::size_t end, unsigned) {
    for (std::size_t p = begin; p < end; ++p) {
      const glm::vec2 v = (*frame.pixels)[p];
      pixel_out[2 * p] = v.x;
      pixel_out[2 * p + 1] = std::isfinite(v.y) && v.y >= 0.0f ? v.y : -1.0f;  // < 0: cannot tell
    }
  });
}

bool RayCache::make_sets(std::string* error) {
  if (pool_ != VK_NULL_HANDLE) return true;
  const uint32_t per_slot = 2 * kBindings + kDeviceRaysBindings + FOVEART_MAX_TABLE_CHUNKS + kPixelsBindings - 1;
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, per_slot * slots_};
  auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = kSetsPerSlot * slots_;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  VkResult r = vkCreateDescriptorPool(device_, &pool_info, nullptr, &pool_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateDescriptorPool (render cache)", r), false;
  std::vector<VkDescriptorSetLayout> layouts;
  for (uint32_t s = 0; s < slots_; ++s) {
    layouts.insert(layouts.end(), {pipelines_.set_layout(), pipelines_.set_layout(),
                                   pipelines_.device_rays_set_layout(), pipelines_.pixels_set_layout()});
  }
  sets_.assign(layouts.size(), VK_NULL_HANDLE);
  written_.assign(layouts.size(), {});
  auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = pool_;
  alloc.descriptorSetCount = uint32_t(layouts.size());
  alloc.pSetLayouts = layouts.data();
  r = vkAllocateDescriptorSets(device_, &alloc, sets_.data());
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateDescriptorSets (render cache)", r), false;
  return true;
}

// Set `index`, naming `buffers` (rewritten only where it named others: its
// slot's last submission, which used it, has finished).
VkDescriptorSet RayCache::set_naming(std::size_t index, std::vector<VkBuffer> buffers, const uint32_t* counts,
                                     uint32_t bindings) {
  if (written_[index] != buffers) {
    std::vector<VkDescriptorBufferInfo> info;
    for (VkBuffer b : buffers) info.push_back({b, 0, VK_WHOLE_SIZE});
    write_storage_descriptors(device_, sets_[index], info.data(), counts, bindings);
    written_[index] = std::move(buffers);
  }
  return sets_[index];
}

VkDescriptorSet RayCache::cache_set(std::uint32_t slot, const RayCacheFrame& frame) {
  const SlotBuffers& upload = frame.device ? device_upload_ : uploads_[slot];
  const VkBuffer control = frame.device ? frame.device->trace.control : counts_.buffer;  // read with a device trace only
  const VkBuffer status = frame.device ? frame.device->trace.status : counts_.buffer;
  return set_naming(slot * kSetsPerSlot + uint32_t(parity_),
                    {current_, anchors_[parity_].buffer, anchors_[1 - parity_].buffer, upload.new_rays.buffer,
                     ray_frame_.buffer, cells_.buffer, by_cell_.buffer, upload.pixels.buffer, counts_.buffer, control,
                     status},
                    kOnes, kBindings);
}

// With a device trace: its rays into the device's new-ray buffer and each pixel's data, on the device.
void RayCache::record_device_inputs(VkCommandBuffer cb, const RayCacheDeviceRays& device, std::uint32_t filter_kind,
                                    std::uint32_t slot) {
  const foveation::GazeMapping& m = device.mapping;
  const TablePack& pack = device.tables->layout();
  const DeviceTraceBuffers& t = device.trace;
  const uint32_t point_count = uint32_t(device.tables->view_tables().points.size());
  CacheDeviceRaysPush rays{{m.screen_width_px, m.screen_height_px},
                           {float(m.canvas_from_screen_x_px), float(m.canvas_from_screen_y_px)},
                           FOVEART_CACHE_DEVICE_RAYS_TRACED,
                           point_count};
  const VkDescriptorSet rays_set = set_naming(
      slot * kSetsPerSlot + 2,
      {t.rays, t.ray_colors, t.point_rays, t.control, t.points, device_upload_.new_rays.buffer, point_farthest_.buffer,
       drawn_.buffer},
      kOnes, kDeviceRaysBindings);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.device_rays());
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.device_rays_layout(), 0, 1, &rays_set, 0,
                          nullptr);
  vkCmdPushConstants(cb, pipelines_.device_rays_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof rays, &rays);
  vkCmdDispatchIndirect(cb, t.control, FOVEART_DEVICE_RESOLVE_DISPATCH * 4);  // the resolve's: a traced point each
  if (device.thins) {  // the fill's: a thinned point each, which has no ray of its own
    compute_barrier(cb);  // both write point_farthest (other points; the barrier keeps the validation's hazards exact)
    rays.pass = FOVEART_CACHE_DEVICE_RAYS_THINNED;
    vkCmdPushConstants(cb, pipelines_.device_rays_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof rays, &rays);
    vkCmdDispatchIndirect(cb, t.control, FOVEART_DEVICE_FILL_DISPATCH * 4);
  }
  compute_barrier(cb);

  CachePixelsPush px{};
  px.screen_px = {m.screen_width_px, m.screen_height_px};
  px.canvas_offset_px = {m.canvas_from_screen_x_px, m.canvas_from_screen_y_px};
  px.canvas_px = {pack.canvas_width_px, pack.canvas_height_px};
  const int tile = foveation::kGatherTilePx;
  px.first_tile = {m.canvas_from_screen_x_px / tile, m.canvas_from_screen_y_px / tile};
  px.k = pack.weighted ? pack.k : pack.neighbor_k;
  px.weighted = pack.weighted ? 1u : 0u;
  px.chunk_count = uint32_t(pack.chunks.size());
  px.filter_kind = filter_kind;
  for (std::size_t c = 0; c < pack.chunks.size(); ++c) set_first_row(px, c, pack.chunks[c].first_row);
  const std::span<const VkBuffer> chunks = device.tables->buffers();
  std::vector<VkBuffer> named;
  for (std::size_t i = 0; i < FOVEART_MAX_TABLE_CHUNKS; ++i) named.push_back(chunks[std::min(i, chunks.size() - 1)]);
  named.insert(named.end(), {device.point_colors, t.points, point_farthest_.buffer, drawn_.buffer,
                             device_upload_.pixels.buffer});
  const VkDescriptorSet pixels_set = set_naming(slot * kSetsPerSlot + 3, std::move(named), kPixelsCounts,
                                                kPixelsBindings);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.pixels());
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.pixels_layout(), 0, 1, &pixels_set, 0,
                          nullptr);
  vkCmdPushConstants(cb, pipelines_.pixels_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof px, &px);
  const int last_tile_x = (m.canvas_from_screen_x_px + m.screen_width_px - 1) / tile;
  const int last_tile_y = (m.canvas_from_screen_y_px + m.screen_height_px - 1) / tile;
  vkCmdDispatch(cb, uint32_t(last_tile_x - px.first_tile.x + 1), uint32_t(last_tile_y - px.first_tile.y + 1), 1);
  compute_barrier(cb);
}

// cache_count, then the cache's four passes (the per-ray ones sized on the device), then cache_count's end.
void RayCache::record_passes(VkCommandBuffer cb, const Frame& f, VkDescriptorSet set) {
  CachePush push = f.push;
  const uint32_t blocks = (push.cell_count + kScanBlock - 1) / kScanBlock;
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.layout(), 0, 1, &set, 0, nullptr);
  auto bind = [&](VkPipeline pipeline, uint32_t phase) {
    push.phase = phase;
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdPushConstants(cb, pipelines_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
  };
  auto dispatch = [&](VkPipeline pipeline, uint32_t phase, uint32_t x, uint32_t y) {
    bind(pipeline, phase);
    vkCmdDispatch(cb, x, y, 1);
    compute_barrier(cb);
  };
  auto per_ray = [&](VkPipeline pipeline) {  // as many workgroups as cache_count wrote for this frame's rays
    bind(pipeline, 0);
    vkCmdDispatchIndirect(cb, counts_.buffer, FOVEART_CACHE_DISPATCH * 4);
    compute_barrier(cb);
  };
  dispatch(pipelines_.count(), FOVEART_CACHE_COUNT_BEGIN, 1, 1);
  per_ray(pipelines_.rays());
  dispatch(pipelines_.scan(), FOVEART_SCAN_BLOCKS, blocks, 1);
  dispatch(pipelines_.scan(), FOVEART_SCAN_BLOCK_SUMS, 1, 1);
  dispatch(pipelines_.scan(), FOVEART_SCAN_ADD_BLOCK_SUMS, groups_for(push.cell_count), 1);
  per_ray(pipelines_.bin());
  dispatch(pipelines_.filter(), 0, (width_px_ + 7) / 8, (height_px_ + 7) / 8);
  dispatch(pipelines_.count(), FOVEART_CACHE_COUNT_END, 1, 1);
}

bool RayCache::record(VkCommandBuffer cb, const RayCacheFrame& frame, const FoveartEyeView& view, std::uint32_t slot,
                      foveation::Executor& executor, std::string* error) {
  const bool device = frame.device.has_value();
  if (slot >= slots_) return *error = "GPU render cache: frame slot " + std::to_string(slot) + " of " +
                                      std::to_string(slots_), false;
  const std::size_t pixels = std::size_t(width_px_) * height_px_;
  if (device ? frame.device->tables == nullptr || frame.device->rays_per_point < 1
             : frame.rays == nullptr || frame.pixels == nullptr || frame.pixels->size() != pixels) {
    return *error = "GPU render cache: the frame's rays or pixels do not match the eye", false;
  }
  std::size_t added = 0;  // the callback's rays, or the most a device trace makes
  if (device) {
    added = frame.device->tables->view_tables().points.size() * frame.device->rays_per_point;
  } else {
    for (const auto& run : *frame.rays) added += run.size();
  }
  Frame f;
  SlotBuffers& upload = device ? device_upload_ : uploads_[slot];
  if (!plan_frame(frame, added, &f, error) || !ensure_capacity(cb, f.rays, added, upload, !device, error) ||
      !make_sets(error) || (device && !ensure_points(frame.device->tables->view_tables().points.size(), error))) {
    return false;
  }
  if (!device) write_upload(frame, upload, executor);
  set_push(frame, view, added, f.push);
  const VkDescriptorSet set = cache_set(slot, frame);
  // Every cell empty (and the first frame's counts); the earlier frame's passes read and wrote these buffers.
  vkCmdFillBuffer(cb, cells_.buffer, 0, VK_WHOLE_SIZE, 0u);
  if (records_ == 0) vkCmdFillBuffer(cb, counts_.buffer, 0, VK_WHOLE_SIZE, 0u);
  if (device) vkCmdFillBuffer(cb, drawn_.buffer, 0, VK_WHOLE_SIZE, 0u);
  memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
  if (device) record_device_inputs(cb, *frame.device, f.push.filter_kind, slot);
  record_passes(cb, f, set);
  added_bound_ = std::move(f.added_bound);
  parity_ ^= 1;  // the kept rays are in the other buffer now
  ++records_;
  return true;
}

bool RayCache::ensure_points(std::size_t point_count, std::string* error) {
  if (point_count <= point_capacity_ && point_farthest_.buffer != VK_NULL_HANDLE) return true;
  retire(point_farthest_);
  point_capacity_ = 0;
  if (!make(point_farthest_, VkDeviceSize{std::max<std::size_t>(point_count, 1)} * 4, false, error)) return false;
  point_capacity_ = point_count;
  return true;
}

void RayCache::set_push(const RayCacheFrame& frame, const FoveartEyeView& view, std::size_t added,
                        CachePush& push) const {
  const foveation::EyePose pose = foveation::eye_pose(view);
  const foveation::EyeFrustum frustum = foveation::eye_frustum(view);
  push.orientation = {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w};
  push.position_m = {pose.position_m.x, pose.position_m.y, pose.position_m.z, 0.0f};
  push.tan_lrud = {frustum.tan_left, frustum.tan_right, frustum.tan_up, frustum.tan_down};
  push.size_px = {int32_t(width_px_), int32_t(height_px_)};
  push.cells_xy = {int32_t(cells_x_), int32_t(cells_y_)};
  push.flags = (frame.restart ? FOVEART_CACHE_RESTART : 0u) | (frame.device ? FOVEART_CACHE_DEVICE_RAYS : 0u);
  push.added = uint32_t(added);  // a device trace's count comes from its control words
  push.filter_kind =
      frame.filter == foveation::PixelFilter::box ? FOVEART_RAY_CACHE_FILTER_BOX : FOVEART_RAY_CACHE_FILTER_BSPLINE2;
  push.cell_count = cells_x_ * cells_y_;
  push.capacity = uint32_t(capacity_);
}

}  // namespace foveart::gpu
