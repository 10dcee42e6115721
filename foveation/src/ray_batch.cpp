#include "foveation/ray_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace foveart::foveation {

void RayBatch::resize(std::size_t ray_count) {
  origins_m_.resize(3 * ray_count);
  directions_.resize(3 * ray_count);
  sample_px_.resize(2 * ray_count);
  rgb_.resize(3 * ray_count);
  depth_m_.resize(ray_count);
  point_index_.resize(ray_count);
}

std::int32_t RayBatch::trace(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                             std::uint64_t frame_index, std::uint32_t ray_count) {
  FoveartRayBatch batch{};
  batch.type = FOVEART_TYPE_RAY_BATCH;
  batch.size = sizeof(FoveartRayBatch);
  batch.frame_index = frame_index;
  batch.view = &view;
  batch.ray_count = ray_count;
  batch.origins_m = origins_m_.data();
  batch.directions = directions_.data();
  batch.sample_px = sample_px_.data();
  batch.point_index = point_index_.data();
  batch.out_rgb = rgb_.data();
  batch.out_depth_m = depth_m_.data();
  std::fill_n(depth_m_.begin(), ray_count, std::numeric_limits<float>::quiet_NaN());  // "not filled"
  try {
    return fn(user_data, &batch);
  } catch (...) {  // ray_trace.h forbids it; an engine that lets one through fails this batch only
    return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  }
}

std::uint64_t RayBatch::invalid_components(std::uint32_t ray_count) const {
  // NaN fails both comparisons, +inf the second. Branch-free over blocks of a
  // fixed length, so that -O2's cheap vectoriser takes the inner loop.
  constexpr std::size_t kBlock = 16;
  const auto is_bad = [](float c) { return std::uint32_t(!((c >= 0.0f) & (c <= std::numeric_limits<float>::max()))); };
  const float* rgb = rgb_.data();
  const std::size_t n = std::size_t(ray_count) * 3;
  std::uint64_t bad = 0;
  std::size_t i = 0;
  for (; i + kBlock <= n; i += kBlock) {
    std::uint32_t block_bad = 0;
    for (std::size_t k = 0; k < kBlock; ++k) block_bad += is_bad(rgb[i + k]);
    bad += block_bad;
  }
  for (; i < n; ++i) bad += is_bad(rgb[i]);
  return bad;
}

}  // namespace foveart::foveation
