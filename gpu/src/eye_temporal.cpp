// Stage 5 of an eye's device frame: the image history (blend, reprojected
// from the history's view), or the render cache writing its frame over the
// gather (the temporal pass then copies it into the output).
#include <cstdint>

#include <glm/gtc/quaternion.hpp>

#include "foveation/eye_rays.hpp"
#include "gpu/eye.hpp"
#include "gpu/shader_interface/temporal.h"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {
namespace {

using shader::TemporalPush;

// foveation::reproject_history's world-space step, folded into one rigid
// transform from this view's space to the last view's.
void set_reprojection(const EyeFrame& frame, TemporalPush& t) {
  const foveation::EyePose now = foveation::eye_pose(frame.view), last = foveation::eye_pose(*frame.history_view);
  const glm::quat q = glm::conjugate(last.orientation) * now.orientation;
  const glm::vec3 translation = glm::conjugate(last.orientation) * (now.position_m - last.position_m);
  const foveation::EyeFrustum fv = foveation::eye_frustum(frame.view), fl = foveation::eye_frustum(*frame.history_view);
  t.reproject = frame.blend.history_sampling == foveation::HistorySampling::catmull_rom ? FOVEART_REPROJECT_CATMULL_ROM
                                                                                         : FOVEART_REPROJECT_BILINEAR;
  t.last_from_view_q = {q.x, q.y, q.z, q.w};
  t.last_from_view_t = {translation.x, translation.y, translation.z, 0.0f};
  t.tan_view = {fv.tan_left, fv.tan_right, fv.tan_up, fv.tan_down};
  t.tan_last = {fl.tan_left, fl.tan_right, fl.tan_up, fl.tan_down};
}

}  // namespace

bool Eye::record_temporal(VkCommandBuffer cb, const EyeFrame& frame, foveation::Executor& executor,
                          std::string* error) {
  if (frame.ray_cache) {  // the render cache writes its frame over the gather; the temporal pass then copies it
    if (ray_cache_ == nullptr) {
      ray_cache_ = std::make_unique<RayCache>(context_, pipelines_.ray_cache(), current_.buffer, width_px_, height_px_,
                                              kFrameSlots);
    }
    RayCacheFrame cache = *frame.ray_cache;
    if (frame.device != nullptr) {  // the device trace's rays, straight from its buffers after the resolve
      cache.device = RayCacheDeviceRays{slot().device_trace->buffers(), slot().colors.buffer, frame.tables, frame.mapping,
                                        frame.device->rays_per_point,
                                        frame.device->density_on() && frame.device->density.thins()};
    }
    if (!ray_cache_->record(cb, cache, frame.view, frame.slot, executor, error)) return false;
    bind_set(cb);
  }
  TemporalPush t{};
  t.size_px = {int32_t(width_px_), int32_t(height_px_)};
  t.current_weight = frame.blend.current_weight;
  t.variance_gamma = frame.blend.variance_gamma;
  t.constraint = frame.blend.constraint == foveation::HistoryClip::variance_clip ? FOVEART_HISTORY_VARIANCE_CLIP
                                                                               : FOVEART_HISTORY_MIN_MAX_CLAMP;
  t.reset = frame.temporal_reset || frame.ray_cache ? 1u : 0u;
  t.clip_floor = frame.blend.clip_floor;
  if (frame.history_view && !frame.temporal_reset && !frame.ray_cache) set_reprojection(frame, t);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.temporal());
  vkCmdPushConstants(cb, pipelines_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof t, &t);
  vkCmdDispatch(cb, (width_px_ + 7) / 8, (height_px_ + 7) / 8, 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShaderRW);
  stamp(cb, 4);
  return true;
}

std::size_t Eye::cached_rays_after_wait() {
  std::size_t kept = 0;
  std::string error;
  if (ray_cache_ != nullptr && !ray_cache_->kept_rays_after_wait(context_, &kept, &error)) return SIZE_MAX;
  return kept;
}

}  // namespace foveart::gpu
