#include "foveation/ray_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "foveation/eye_rays.hpp"

namespace foveart::foveation {

void RayBatch::resize(std::size_t ray_count) {
  origins_m_.resize(3 * ray_count);
  directions_.resize(3 * ray_count);
  sample_px_.resize(2 * ray_count);
  rgb_.resize(3 * ray_count);
  depth_m_.resize(ray_count);
  point_index_.resize(ray_count);
}

// Blocks of a fixed length in structure-of-arrays form, so that the compiler
// vectorises the square roots and divisions (this file is built with -O3
// -fno-math-errno): set ray by ray, they were the set-up's largest cost.
// Each component in the order of eye_ray_direction(map, px), so the bits agree.
void RayBatch::aim(const FoveartEyeView& view, std::uint32_t ray_count) {
  const EyePose pose = eye_pose(view);
  const ScreenRayMap map = screen_ray_map(eye_frustum(view), pose);
  constexpr std::size_t kBlock = 16;
  const float* sample = sample_px_.data();
  float* dir = directions_.data();
  const auto aim_block = [&](std::size_t first, std::size_t count) {
    float x[kBlock], y[kBlock], z[kBlock], inv_len[kBlock];
    for (std::size_t k = 0; k < count; ++k) {
      const float sx = sample[2 * (first + k)], sy = sample[2 * (first + k) + 1];
      x[k] = (map.top_left.x + sx * map.per_px_right.x) + sy * map.per_px_down.x;
      y[k] = (map.top_left.y + sx * map.per_px_right.y) + sy * map.per_px_down.y;
      z[k] = (map.top_left.z + sx * map.per_px_right.z) + sy * map.per_px_down.z;
    }
    for (std::size_t k = 0; k < count; ++k) inv_len[k] = 1.0f / std::sqrt((x[k] * x[k] + y[k] * y[k]) + z[k] * z[k]);
    for (std::size_t k = 0; k < count; ++k) {
      float* d = dir + 3 * (first + k);
      d[0] = x[k] * inv_len[k];
      d[1] = y[k] * inv_len[k];
      d[2] = z[k] * inv_len[k];
    }
  };
  std::size_t first = 0;
  for (; first + kBlock <= ray_count; first += kBlock) aim_block(first, kBlock);
  if (first < ray_count) aim_block(first, ray_count - first);
  float* origin = origins_m_.data();
  for (std::size_t i = 0; i < ray_count; ++i) {
    origin[3 * i] = pose.position_m.x;
    origin[3 * i + 1] = pose.position_m.y;
    origin[3 * i + 2] = pose.position_m.z;
  }
}

std::int32_t RayBatch::trace(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                             std::uint64_t frame_index, std::uint32_t ray_count) {
  aim(view, ray_count);
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
