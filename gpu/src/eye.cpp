#include "gpu/eye.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <iterator>

#include "gpu/shader_interface/device_trace.h"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {

EyeFrame EyeFrame::of(const Tables& tables, const foveation::FrameHandOff& frame, bool srgb) {
  const foveation::TracedPoints& traced = *frame.traced;
  EyeFrame f;
  f.tables = &tables;
  f.colors = &traced.colors;
  f.point_depth_m = &traced.depth_m;
  f.traced = traced.runs;
  f.mapping = frame.mapping;
  f.rbf_clamp = frame.rbf_clamp;
  f.view = frame.view;
  f.srgb = srgb;
  f.set_temporal(traced, frame.temporal);
  return f;
}

void EyeFrame::set_temporal(const foveation::TracedPoints& points, const foveation::TemporalFrame& temporal) {
  temporal_reset = temporal.reset;
  blend = temporal.blend;  // current_weight: this frame's, the CPU's weight rule for both paths
  history_view = temporal.history_view;
  ray_cache.reset();
  // A render cache reprojects its rays itself; its frame has no history_view.
  if (temporal.rays) {
    RayCacheFrame c;
    c.rays = &points.rays;
    c.pixels = temporal.ray_pixels;
    c.restart = temporal.ray_restart;
    c.filter = temporal.ray_filter;
    c.max_age_frames = temporal.ray_max_age_frames;
    ray_cache = c;
  }
}

Eye::Eye(Context& context, const FramePipelines& pipelines, uint32_t width_px, uint32_t height_px)
    : context_(context), pipelines_(pipelines), device_(context.vk_device()), width_px_(width_px),
      height_px_(height_px) {}

std::unique_ptr<Eye> Eye::create(Context& context, const FramePipelines& pipelines, uint32_t width_px,
                                 uint32_t height_px, std::string* error) {
  std::unique_ptr<Eye> e(new Eye(context, pipelines, width_px, height_px));
  if (!e->create_buffers(error)) return nullptr;
  return e;
}

bool Eye::create_buffers(std::string* error) {
  const VkDeviceSize pixels = VkDeviceSize{width_px_} * height_px_;
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  const VkBufferUsageFlags shown = storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const VkDeviceSize tile_words =
      FOVEART_DEVICE_TILES_HEADER_WORDS + FOVEART_DEVICE_TILE_REGIONS * device_tile_capacity(width_px_, height_px_);
  if (!context_.create_buffer(&current_, pixels * 16, storage, false, error) ||
      !context_.create_buffer(&history_[0], pixels * 16, storage, false, error) ||
      !context_.create_buffer(&history_[1], pixels * 16, storage, false, error) ||
      !context_.create_buffer(&shown_, pixels * 4, shown, false, error) ||
      !context_.create_buffer(&tiles_, tile_words * 4, storage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false, error)) {
    return false;
  }
  std::array<VkDescriptorSetLayout, 2 * kFrameSlots> layouts;
  layouts.fill(pipelines_.set_layout());
  std::array<VkDescriptorSet, 2 * kFrameSlots> sets{};
  if (!allocate_storage_sets(device_, layouts.data(), uint32_t(layouts.size()),
                             uint32_t(layouts.size()) * kFrameStorageBuffers, &pool_, sets.data(), error)) {
    return false;
  }
  for (uint32_t s = 0; s < kFrameSlots; ++s) {
    slots_[s].sets[0] = sets[2 * s];
    slots_[s].sets[1] = sets[2 * s + 1];
    if (!create_slot(slots_[s], error)) return false;
  }
  return true;
}

// A slot's status (read by the host) and timestamp queries.
bool Eye::create_slot(Slot& slot, std::string* error) {
  if (!context_.create_buffer(&slot.status, FOVEART_DEVICE_STATUS_WORDS * 4,
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, error)) {
    return false;
  }
  if (!context_.timestamps()) return true;
  auto query_info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
  query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  query_info.queryCount = StageTimes::kTimestamps;
  const VkResult r = vkCreateQueryPool(device_, &query_info, nullptr, &slot.queries);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateQueryPool", r), false;
  return true;
}

Eye::~Eye() {
  ray_cache_ = nullptr;
  for (Slot& slot : slots_) {
    slot.device_trace = nullptr;
    if (slot.queries != VK_NULL_HANDLE) vkDestroyQueryPool(device_, slot.queries, nullptr);
    for (BoundBuffer* b : {&slot.upload, &slot.colors, &slot.point_depth, &slot.status}) destroy_buffer(device_, b);
  }
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  for (BoundBuffer* b : {&current_, &history_[0], &history_[1], &shown_, &readback_, &tiles_})
    destroy_buffer(device_, b);
}

bool Eye::ensure_points(Slot& slot, std::size_t point_count, std::string* error) {
  if (point_count <= slot.point_capacity) return true;
  for (BoundBuffer* b : {&slot.upload, &slot.colors, &slot.point_depth}) destroy_buffer(device_, b);
  slot.point_capacity = 0;
  const VkDeviceSize bytes = VkDeviceSize{point_count} * 16;
  // Colours: also copied out for the tests (read_point_colors).
  const VkBufferUsageFlags filled = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  // The upload: entries, then a depth each (shaders/common.glsl Upload).
  if (!context_.create_buffer(&slot.upload, bytes + VkDeviceSize{point_count} * 4 + 16,
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, error) ||
      !context_.create_buffer(&slot.colors, bytes, filled | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, error) ||
      !context_.create_buffer(&slot.point_depth, VkDeviceSize{point_count} * 4, filled, false, error)) {
    return false;
  }
  slot.point_capacity = point_count;
  slot.bound_tables = nullptr;  // descriptors name the old buffers
  return true;
}

void Eye::update_descriptors(Slot& slot) {
  const std::span<const VkBuffer> buffers = slot.bound_tables->buffers();
  VkDescriptorBufferInfo chunks[kMaxTableChunks];
  for (std::size_t i = 0; i < kMaxTableChunks; ++i) {
    // Unused slots repeat the last chunk: every descriptor of the array is valid.
    chunks[i] = {buffers[std::min(i, buffers.size() - 1)], 0, VK_WHOLE_SIZE};
  }
  for (int s = 0; s < 2; ++s) {
    VkDescriptorBufferInfo info[kFrameStorageBuffers] = {};
    std::copy(std::begin(chunks), std::end(chunks), info);
    const VkDescriptorBufferInfo rest[kFrameBindings - 1] = {
        {slot.colors.buffer, 0, VK_WHOLE_SIZE},  {current_.buffer, 0, VK_WHOLE_SIZE},
        {history_[s].buffer, 0, VK_WHOLE_SIZE},  {history_[1 - s].buffer, 0, VK_WHOLE_SIZE},
        {slot.upload.buffer, 0, VK_WHOLE_SIZE},  {shown_.buffer, 0, VK_WHOLE_SIZE},
        {slot.point_depth.buffer, 0, VK_WHOLE_SIZE}, {slot.status.buffer, 0, VK_WHOLE_SIZE}};
    std::copy(std::begin(rest), std::end(rest), info + kMaxTableChunks);
    write_storage_descriptors(device_, slot.sets[s], info, kFrameDescriptorCounts, kFrameBindings);
  }
}

void Eye::bind_set(VkCommandBuffer cb) const {
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.layout(), 0, 1, &slot().sets[parity_], 0,
                          nullptr);
}

bool Eye::check_frame(const EyeFrame& frame, std::string* error) const {
  const auto& m = frame.mapping;
  if (uint32_t(m.screen_width_px) != width_px_ || uint32_t(m.screen_height_px) != height_px_) {
    return *error = "GPU eye is " + std::to_string(width_px_) + "x" + std::to_string(height_px_) + ", the frame " +
                    std::to_string(m.screen_width_px) + "x" + std::to_string(m.screen_height_px),
           false;
  }
  if (frame.slot >= kFrameSlots) return *error = "GPU frame: no frame slot " + std::to_string(frame.slot), false;
  const std::size_t point_count = frame.tables->view_tables().points.size();
  if (frame.device == nullptr && (frame.colors == nullptr || frame.colors->size() != point_count)) {
    return *error = "GPU frame: point colours do not match the tables", false;
  }
  std::size_t traced_points = 0;
  for (const auto& run : frame.traced) traced_points += run.size();
  if (traced_points > point_count) return *error = "GPU frame: more traced points than points", false;
  return true;
}

bool Eye::begin_frame(VkCommandBuffer cb, const EyeFrame& frame, std::string* error) {
  if (!check_frame(frame, error)) return false;
  slot_ = last_slot_ = frame.slot;
  Slot& s = slot();
  s.recorded = s.density = false;
  host_written_ = 0;
  host_read_ = 0;
  if (!ensure_points(s, frame.tables->view_tables().points.size(), error)) return false;
  if (s.bound_tables != frame.tables) {
    s.bound_tables = frame.tables;
    update_descriptors(s);
  }
  if (s.queries != VK_NULL_HANDLE) vkCmdResetQueryPool(cb, s.queries, 0, StageTimes::kTimestamps);
  after_earlier_submissions(cb);  // earlier frames' passes read and wrote the shared buffers
  vkCmdFillBuffer(cb, s.status.buffer, 0, VK_WHOLE_SIZE, 0u);  // no fault yet; the resolve counts them
  if (!shown_cleared_) {
    vkCmdFillBuffer(cb, shown_.buffer, 0, VK_WHOLE_SIZE, 0xFF000000u);  // opaque black
    vkCmdFillBuffer(cb, tiles_.buffer, 0, VK_WHOLE_SIZE, 0u);           // no contrast measured
  }
  shown_cleared_ = true;
  // The last frame measured the tiles and ended (end_frame), on these tables (a new set starts anew, as on the CPU).
  tiles_measured_ = ended_measuring_ && measured_tables_ == frame.tables;
  measured_tables_ = frame.tables;
  ended_measuring_ = false;
  return true;
}

void Eye::after_earlier_submissions(VkCommandBuffer cb) {
  memory_barrier(cb, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 kShaderRW | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

void Eye::end_frame() {
  parity_ ^= 1;  // this frame's output is the next frame's history
  slot().recorded = true;
  ended_measuring_ = slot().density;
}

bool Eye::record(VkCommandBuffer cb, const EyeFrame& frame, VkImage image, foveation::Executor& executor,
                 std::string* error) {
  if (!begin_frame(cb, frame, error)) return false;
  const std::size_t uploaded = frame.device == nullptr ? upload_traced(frame, executor) : 0;
  if (!record_trace(cb, frame, error)) return false;           // stages 1-3 on the device, or the slots cleared
  record_scatter(cb, frame, uploaded);                         // stage 4
  record_gather(cb, frame);
  if (!record_temporal(cb, frame, executor, error)) return false;  // stage 5
  record_encode(cb, frame, image);                                 // stage 6
  end_frame();
  return true;
}

void Eye::stamp(VkCommandBuffer cb, uint32_t query) const {
  if (slot().queries != VK_NULL_HANDLE) {
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, slot().queries, query);
  }
}

bool Eye::stage_times(std::uint32_t slot, StageTimes* out) const {
  if (slot >= kFrameSlots || !slots_[slot].recorded || slots_[slot].queries == VK_NULL_HANDLE) return false;
  uint64_t t[StageTimes::kTimestamps] = {};
  if (vkGetQueryPoolResults(device_, slots_[slot].queries, 0, StageTimes::kTimestamps, sizeof t, t, sizeof(uint64_t),
                            VK_QUERY_RESULT_64_BIT) != VK_SUCCESS) {
    return false;
  }
  host_read_ += sizeof t;
  const double ms = double(context_.timestamp_period_ns()) * 1e-6;
  auto span = [&](int a) { return float(double(t[a + 1] - t[a]) * ms); };
  *out = StageTimes{span(0), span(6), span(7), span(1), span(2), span(3), span(4)};
  if (!slots_[slot].density) out->density_fill_ms = out->density_contrast_ms = 0;  // empty: the stamps' own cost
  return true;
}

DeviceTraceStatus Eye::device_trace_status(std::uint32_t slot) const {
  DeviceTraceStatus s;
  if (slot >= kFrameSlots || slots_[slot].device_trace == nullptr || slots_[slot].status.mapped == nullptr) return s;
  uint32_t words[FOVEART_DEVICE_STATUS_WORDS] = {};
  std::memcpy(words, slots_[slot].status.mapped, sizeof words);
  host_read_ += sizeof words;
  s.invalid_components = words[FOVEART_DEVICE_STATUS_INVALID_COMPONENTS];
  s.visible_points = words[FOVEART_DEVICE_STATUS_VISIBLE_POINTS];
  s.traced_points = words[FOVEART_DEVICE_STATUS_TRACED_POINTS];
  s.thinned_points = words[FOVEART_DEVICE_STATUS_THINNED_POINTS];
  s.rays = words[FOVEART_DEVICE_STATUS_RAYS];
  return s;
}

bool Eye::read_point_colors(std::uint32_t slot, std::vector<float>* rgba, std::string* error) {
  if (slot >= kFrameSlots || slots_[slot].colors.buffer == VK_NULL_HANDLE) return *error = "no point colours", false;
  BoundBuffer copy;
  const VkDeviceSize bytes = slots_[slot].colors.size;
  if (!context_.create_buffer(&copy, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, error)) return false;
  const bool ok = context_.submit_and_wait(
      [&](VkCommandBuffer cb) {
        memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_TRANSFER_READ_BIT);
        const VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cb, slots_[slot].colors.buffer, copy.buffer, 1, &region);
        memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_HOST_READ_BIT);
        return true;
      },
      error);
  if (ok) {
    rgba->resize(std::size_t(bytes / 4));
    std::memcpy(rgba->data(), copy.mapped, std::size_t(bytes));
  }
  destroy_buffer(device_, &copy);
  return ok;
}

bool Eye::read_rgba8(std::vector<std::uint8_t>* out, std::string* error) {
  const VkDeviceSize bytes = VkDeviceSize{width_px_} * height_px_ * 4;
  if (readback_.buffer == VK_NULL_HANDLE &&
      !context_.create_buffer(&readback_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, error)) {
    return false;
  }
  const bool ok = context_.submit_and_wait(
      [&](VkCommandBuffer cb) {
        memory_barrier(cb, kCompute | VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        const VkBufferCopy copy{0, 0, bytes};
        vkCmdCopyBuffer(cb, shown_.buffer, readback_.buffer, 1, &copy);
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

}  // namespace foveart::gpu
