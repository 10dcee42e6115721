#include "foveation/point_rays.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace foveart::foveation {
namespace {

// Disc offsets are precomputed up to this many samples (64 MB); beyond, made per frame.
constexpr std::size_t kMaxPrecomputedSamples = std::size_t{8} << 20;

}  // namespace

PointRays::PointRays(const PointSet& points, int rays_per_point, PixelFilter pixel_filter, bool jitter_each_frame)
    : points_(points),
      rays_per_point_(std::uint32_t(rays_per_point)),
      pixel_filter_(pixel_filter),
      jitter_each_frame_(jitter_each_frame) {
  if (rays_per_point < 1 || rays_per_point > kMaxRaysPerPoint)
    throw std::invalid_argument("point rays: rays per point must be in 1.." + std::to_string(kMaxRaysPerPoint));
}

void PointRays::prepare(std::uint64_t seed, Executor& executor) {
  const std::uint32_t spp = rays_per_point_;
  precomputed_ = !jitter_each_frame_ && points_.size() * spp <= kMaxPrecomputedSamples;
  if (precomputed_ && (offset_px_.empty() || seed_ != seed)) {
    offset_px_.resize(points_.size() * spp);
    executor.parallel_chunks(points_.size(), 16384, [&](std::size_t first, std::size_t last, unsigned) {
      for (std::size_t i = first; i < last; ++i) {
        if (points_.on_pixel_grid(i)) continue;
        for (std::uint32_t s = 0; s < spp; ++s)
          offset_px_[i * spp + s] = unit_disc_sample(seed, std::uint32_t(i), int(s)) * points_.radius_px[i];
      }
    });
  }
  seed_ = seed;
}

std::uint32_t point_ray_count(std::uint32_t rays_per_point, float radius_px, float tile_contrast, float rays_contrast) {
  const float disc_share = std::min(1.0f, radius_px * radius_px);  // pi r^2 / (pi 1^2)
  const float contrast_share = std::min(1.0f, tile_contrast / rays_contrast);  // +inf (none measured yet): all
  const float rays = std::ceil(float(rays_per_point) * disc_share * contrast_share * contrast_share);
  return rays >= 1.0f ? std::min(rays_per_point, std::uint32_t(rays)) : 1u;
}

RaysContrastSteps rays_contrast_steps(float rays_contrast, float doubling_ecc_deg, double view_distance_px) {
  RaysContrastSteps steps;
  steps.rays_contrast = rays_contrast;
  if (!(doubling_ecc_deg > 0.0f)) return steps;
  for (int k = 0; k < kRaysContrastSteps; ++k) {
    const double ecc_rad = double(k + 1) * double(doubling_ecc_deg) * (std::numbers::pi / 180.0);
    if (ecc_rad >= 0.5 * std::numbers::pi) break;
    const double distance_px = view_distance_px * std::tan(ecc_rad);  // eccentricity_deg's inverse
    steps.distance_sq_px2[std::size_t(k)] = float(distance_px * distance_px);
  }
  return steps;
}

std::uint32_t PointRays::rays_of(std::uint32_t id, float tile_contrast, const RaysContrastSteps& rays_contrast) const {
  if (points_.in_exact_fovea(id)) return rays_per_point_;
  const glm::vec2 from_centre = points_.from_centre_px(id);
  const float contrast = rays_contrast.at(from_centre.x, from_centre.y);
  return point_ray_count(rays_per_point_, points_.radius_px[id], tile_contrast, contrast);
}

std::uint32_t PointRays::set_rays(RayBatch& batch, std::span<const std::uint32_t> ids, const VisibleRegion& region,
                                  int screen_width_px, std::span<const std::uint32_t> counts) const {
  const std::uint32_t spp = rays_per_point_;
  std::size_t slot = 0;
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const std::uint32_t id = ids[j];
    const glm::vec2 screen_px = region.to_screen(points_.position_px[id]);
    const bool on_grid = points_.on_pixel_grid(id);
    const std::uint32_t rays = counts.empty() ? spp : std::min(spp, counts[j]);
    for (std::uint32_t s = 0; s < rays; ++s, ++slot) {
      const glm::vec2 sample_px =
          on_grid      ? pixel_sample_px(screen_px, int(s), seed_, screen_width_px, pixel_filter_)
          : precomputed_ ? screen_px + offset_px_[std::size_t(id) * spp + s]
                         : screen_px + unit_disc_sample(seed_, id, int(s)) * points_.radius_px[id];
      batch.set_sample(slot, sample_px, id);
    }
  }
  return std::uint32_t(slot);
}

}  // namespace foveart::foveation
