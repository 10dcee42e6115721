// The one builder of engine callback batches (ray_trace.h): rays through
// screen positions of an eye view, kept from call to call so that nothing is
// allocated per batch once it has grown to the batch size. The foveated frame
// and the full render both fill these.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "foveation/ray_trace.h"

namespace foveart::foveation {

class RayBatch {
 public:
  void resize(std::size_t ray_count);
  std::size_t capacity() const { return point_index_.size(); }

  // Ray i through screen position sample_px of the view trace() is given, for point `point`.
  void set_sample(std::size_t i, glm::vec2 sample_px, std::uint32_t point) {
    sample_px_[2 * i] = sample_px.x;
    sample_px_[2 * i + 1] = sample_px.y;
    point_index_[i] = point;
  }

  // Aims rays [0, ray_count) from the view's eye through their samples, calls
  // fn for them and returns its status; a C++ exception from an engine without
  // its own barrier becomes ENGINE_FAILURE.
  std::int32_t trace(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view, std::uint64_t frame_index,
                     std::uint32_t ray_count);

  // Where ray i crosses the screen, and the point it was set for (set_sample).
  glm::vec2 sample_px(std::size_t i) const { return glm::vec2(sample_px_[2 * i], sample_px_[2 * i + 1]); }
  std::uint32_t point(std::size_t i) const { return point_index_[i]; }
  glm::vec3 rgb(std::size_t i) const { return glm::vec3(rgb_[3 * i], rgb_[3 * i + 1], rgb_[3 * i + 2]); }
  // Distance to the hit along ray i (+inf: a miss); NaN when the engine returns no depth.
  float depth_m(std::size_t i) const { return depth_m_[i]; }
  // Colour components of rays [0, ray_count) that are NaN, infinite or negative.
  std::uint64_t invalid_components(std::uint32_t ray_count) const;

 private:
  // Origins and unit directions of rays [0, ray_count): eye_ray_direction(map, sample) for each.
  void aim(const FoveartEyeView& view, std::uint32_t ray_count);

  std::vector<float> origins_m_, directions_, sample_px_, rgb_, depth_m_;
  std::vector<std::uint32_t> point_index_;
};

}  // namespace foveart::foveation
