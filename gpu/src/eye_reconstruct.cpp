// Stages 1-4 of an eye's device frame: the traced points' colours and depths
// up (or, with a device trace, stages 1-3 recorded by DeviceTrace into the
// same slots), scattered into their slots, and every pixel gathered from them.
#include <cstring>

#include "gpu/eye.hpp"
#include "gpu/shader_depth.hpp"
#include "gpu/shader_interface/gather.h"
#include "gpu/shader_interface/scatter.h"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {
namespace {

using shader::GatherPush;
using shader::ScatterPush;

// Chunk c's first tile row, into the uvec4s the push constants hold them in.
void set_first_row(GatherPush& g, std::size_t c, uint32_t row) {
  shader::uvec4& v = g.chunk_first_row[c / 4];
  switch (c % 4) {
    case 0: v.x = row; break;
    case 1: v.y = row; break;
    case 2: v.z = row; break;
    default: v.w = row; break;
  }
}

uint32_t groups(uint32_t n, uint32_t size) { return (n + size - 1) / size; }

}  // namespace

// The traced colours, run by run into the upload buffer: (point, rgb) per entry, then a depth each.
std::size_t Eye::upload_traced(const EyeFrame& frame, foveation::Executor& executor) {
  const std::size_t point_count = frame.tables->view_tables().points.size();
  std::vector<std::size_t> first(frame.traced.size() + 1, 0);
  for (std::size_t i = 0; i < frame.traced.size(); ++i) first[i + 1] = first[i] + frame.traced[i].size();
  const std::size_t uploaded = first.back();  // at most point_count (record)
  if (uploaded == 0) return 0;
  auto* entries = static_cast<uint32_t*>(slot().upload.mapped);
  auto* depths = reinterpret_cast<float*>(entries + uploaded * 4);  // shaders/common.glsl Upload
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
  return uploaded;
}

namespace {

// Every point's slot "not traced" (a = 0) with an unknown depth.
void clear_slots(VkCommandBuffer cb, VkBuffer colors, VkBuffer point_depth) {
  vkCmdFillBuffer(cb, colors, 0, VK_WHOLE_SIZE, 0u);
  uint32_t unknown_bits = 0;
  std::memcpy(&unknown_bits, &kDepthUnknown, 4);
  vkCmdFillBuffer(cb, point_depth, 0, VK_WHOLE_SIZE, unknown_bits);
  memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShaderRW);
}

}  // namespace

bool Eye::ensure_device_trace(Slot& s, std::string* error) {
  if (s.device_trace != nullptr) return true;
  const DeviceTracePipelines* pipelines = pipelines_.device_trace(error);
  if (pipelines == nullptr) return false;
  s.device_trace = std::make_unique<DeviceTrace>(context_, *pipelines);
  return true;
}

bool Eye::record_app_rays(VkCommandBuffer cb, std::uint32_t slot_index, const Tables& tables,
                          const DeviceTraceFrame& frame, DeviceRayBatch* out_batch, std::string* error) {
  if (slot_index >= kFrameSlots) return *error = "GPU frame: no frame slot " + std::to_string(slot_index), false;
  Slot& s = slots_[slot_index];
  if (!ensure_points(s, tables.view_tables().points.size(), error) || !ensure_device_trace(s, error)) return false;
  DeviceTraceTargets targets{s.colors.buffer, s.point_depth.buffer, s.status.buffer, tiles_.buffer};
  // The acquire comes after the last frame's record: its content density reads that frame's tiles,
  // as begin_frame will decide for this frame.
  targets.tiles_measured = ended_measuring_ && measured_tables_ == &tables;
  after_earlier_submissions(cb);  // they wrote the tiles and read the buffers the rays go into
  if (!s.device_trace->record_rays(cb, frame, targets, error)) return false;
  *out_batch = s.device_trace->batch(frame, VK_NULL_HANDLE);
  return true;
}

// Stages 1-3 on the device, resolved into the slots (a device-traced frame; else nothing but the timestamps).
// An app-recorded trace's rays are in the slot already (record_app_rays): its colours are resolved only.
// Content density's passes after the resolve are timed on their own (StageTimes::density_*_ms).
bool Eye::record_trace(VkCommandBuffer cb, const EyeFrame& frame, std::string* error) {
  stamp(cb, 0);
  Slot& s = slot();
  if (frame.device != nullptr) {
    clear_slots(cb, s.colors.buffer, s.point_depth.buffer);
    if (!ensure_device_trace(s, error)) return false;
    DeviceTraceTargets targets{s.colors.buffer, s.point_depth.buffer, s.status.buffer, tiles_.buffer};
    targets.tiles_measured = tiles_measured_;
    if (frame.device->app_trace) {
      s.device_trace->record_resolve(cb, *frame.device);
    } else if (!s.device_trace->record(cb, *frame.device, targets, error)) {
      return false;
    }
    host_written_ += s.device_trace->host_bytes_written();
  }
  stamp(cb, 6);
  if (frame.device != nullptr) s.device_trace->record_fill(cb, *frame.device);
  stamp(cb, 7);
  if (frame.device != nullptr) s.device_trace->record_contrast(cb, *frame.device);
  stamp(cb, 8);
  s.density = frame.device != nullptr && frame.device->density_on();
  stamp(cb, 1);
  return true;
}

// Stage 4, first half: the uploaded colours into their slots.
void Eye::record_scatter(VkCommandBuffer cb, const EyeFrame& frame, std::size_t uploaded) {
  bind_set(cb);
  if (frame.device == nullptr) {
    clear_slots(cb, slot().colors.buffer, slot().point_depth.buffer);
    if (uploaded > 0) {
      vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.scatter());
      const ScatterPush push{uint32_t(uploaded), uint32_t(frame.tables->view_tables().points.size())};
      vkCmdPushConstants(cb, pipelines_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
      vkCmdDispatch(cb, groups(uint32_t(uploaded), 64), 1, 1);
    }
  }
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  stamp(cb, 2);
}

// Stage 4, second half: every pixel from its taps (one workgroup per 8x8 canvas tile).
void Eye::record_gather(VkCommandBuffer cb, const EyeFrame& frame) {
  const TablePack& pack = frame.tables->layout();
  const auto& m = frame.mapping;
  GatherPush g{};
  g.screen_px = {m.screen_width_px, m.screen_height_px};
  g.canvas_offset_px = {m.canvas_from_screen_x_px, m.canvas_from_screen_y_px};
  g.canvas_px = {pack.canvas_width_px, pack.canvas_height_px};
  const int tile = foveation::kGatherTilePx;
  g.first_tile = {m.canvas_from_screen_x_px / tile, m.canvas_from_screen_y_px / tile};
  const int last_tile_x = (m.canvas_from_screen_x_px + m.screen_width_px - 1) / tile;
  const int last_tile_y = (m.canvas_from_screen_y_px + m.screen_height_px - 1) / tile;
  g.k = pack.k;
  g.neighbor_k = pack.neighbor_k;
  g.flags = (pack.weighted ? FOVEART_GATHER_WEIGHTED : 0u) | (pack.f16 ? FOVEART_GATHER_F16 : 0u) |
            (pack.rbf ? FOVEART_GATHER_RBF : 0u);
  if (pack.rbf && frame.rbf_clamp == foveation::RbfClamp::taps) g.flags |= FOVEART_GATHER_CLAMP_TAPS;
  if (pack.rbf && frame.rbf_clamp == foveation::RbfClamp::block) g.flags |= FOVEART_GATHER_CLAMP_BLOCK;
  g.chunk_count = uint32_t(pack.chunks.size());
  g.fallback_rgb = {frame.fallback_rgb[0], frame.fallback_rgb[1], frame.fallback_rgb[2], 0.0f};
  for (std::size_t c = 0; c < pack.chunks.size(); ++c) set_first_row(g, c, pack.chunks[c].first_row);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.gather());
  vkCmdPushConstants(cb, pipelines_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof g, &g);
  vkCmdDispatch(cb, uint32_t(last_tile_x - g.first_tile.x + 1), uint32_t(last_tile_y - g.first_tile.y + 1), 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  stamp(cb, 3);
}

}  // namespace foveart::gpu
