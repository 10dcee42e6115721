// How an engine reads a FoveartRayBatch (ray_trace.h): the batch checked once,
// then each ray's origin and unit direction, whether the batch gives the rays
// themselves or a view and the rays' screen positions. The one reading of the
// callback contract that the sample engines (CPU and GPU) share.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "foveation/eye_rays.hpp"
#include "foveation/eye_view_check.hpp"
#include "foveation/ray_trace.h"

namespace foveart::foveation {

class RayBatchReader {
 public:
  // FOVEART_RESULT_SUCCESS with *out ready to read, or FOVEART_RESULT_ERROR_INVALID_ARGUMENT
  // for a batch an engine must refuse: no (type, size) header, no out_rgb, or neither
  // origins and directions nor a view with sample positions that a frame can be traced
  // from (eye_view_problem). A batch of no rays is valid whatever its arrays.
  static std::int32_t read(const FoveartRayBatch* batch, RayBatchReader* out) {
    if (!batch || batch->type != FOVEART_TYPE_RAY_BATCH ||
        batch->size < offsetof(FoveartRayBatch, out_rgb) + sizeof(float*))
      return FOVEART_RESULT_ERROR_INVALID_ARGUMENT;
    out->batch_ = batch;
    if (batch->ray_count == 0) return FOVEART_RESULT_SUCCESS;
    const bool explicit_rays = batch->origins_m && batch->directions;
    const bool view_rays = batch->view && batch->sample_px && batch->view->type == FOVEART_TYPE_EYE_VIEW &&
                           batch->view->size >= sizeof(FoveartEyeView) && eye_view_problem(*batch->view).empty();
    if (!batch->out_rgb || (!explicit_rays && !view_rays)) return FOVEART_RESULT_ERROR_INVALID_ARGUMENT;
    out->explicit_rays_ = explicit_rays;
    if (!explicit_rays) {
      const EyePose pose = eye_pose(*batch->view);
      out->eye_m_ = pose.position_m;
      out->ray_map_ = screen_ray_map(eye_frustum(*batch->view), pose);
    }
    return FOVEART_RESULT_SUCCESS;
  }

  const FoveartRayBatch& batch() const { return *batch_; }
  std::uint32_t size() const { return batch_->ray_count; }

  // Ray r with its direction normalised; false for a ray that cannot be traced (a zero or
  // non-finite direction, an origin that is not finite or lies beyond kMaxPositionM), which the
  // engine answers with black and no depth.
  bool ray(std::uint32_t r, glm::vec3* origin_m, glm::vec3* direction) const {
    glm::vec3 o, d;
    if (explicit_rays_) {
      o = glm::vec3(batch_->origins_m[3 * r], batch_->origins_m[3 * r + 1], batch_->origins_m[3 * r + 2]);
      d = glm::vec3(batch_->directions[3 * r], batch_->directions[3 * r + 1], batch_->directions[3 * r + 2]);
    } else {
      o = eye_m_;
      d = eye_ray_direction(ray_map_, glm::vec2(batch_->sample_px[2 * r], batch_->sample_px[2 * r + 1]));
    }
    const float len2 = glm::dot(d, d);
    if (!(len2 > 0.0f) || !std::isfinite(len2) || !traceable_position(o)) return false;
    *origin_m = o;
    *direction = d * (1.0f / std::sqrt(len2));
    return true;
  }

  // Where the engine writes each ray's hit distance, when the batch has room for it; else nullptr.
  float* out_depth_m() const {
    return batch_->size >= FOVEART_RAY_BATCH_SIZE_WITH_DEPTH ? batch_->out_depth_m : nullptr;
  }

 private:
  const FoveartRayBatch* batch_ = nullptr;
  bool explicit_rays_ = false;
  glm::vec3 eye_m_{0.0f};
  ScreenRayMap ray_map_{};
};

}  // namespace foveart::foveation
