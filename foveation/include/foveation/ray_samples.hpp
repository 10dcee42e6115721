// Per-point ray sample positions (thesis 4.2): spp positions uniformly inside
// each visible point's disc, from a per-point fixed seed, so a static gaze gives
// identical frames; a pixel-grid point's spread over its screen pixel exactly
// as the full render spreads that pixel's (same positions for the same seed),
// drawn from the pixel filter (PixelFilter).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/point_set.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::foveation {

// Contiguous arrays ready for a FoveartRayBatch: sample s of visible point v sits
// at [v * spp + s]; point_index holds the point set index of its point.
struct RaySamples {
  int spp = 0;
  std::vector<glm::vec2> sample_px;
  std::vector<std::uint32_t> point_index;

  std::size_t size() const { return sample_px.size(); }
};

// The filter a pixel's rays are drawn from: a pixel's value is the filter-
// weighted mean of the image around its centre, estimated by averaging rays
// whose offsets follow the filter (importance sampling, pbrt-v4 8.8).
//  * box: uniform over the pixel (the thesis's). The sharpest, and the one
//    that aliases most: detail finer than a pixel changes a pixel's value as
//    it crosses the grid, which a moving head sees as trembling edges.
//  * bspline2: the quadratic B-spline, box * box * box (Unser 1999): support
//    3 px, sigma 0.5 px (pbrt-v4's default Gaussian has the same sigma), each
//    offset the sum of three uniforms. Softer, and smooth enough that a
//    reprojected temporal history follows the image under sub-pixel motion
//    (docs/foveation.md, "The pixel filter").
enum class PixelFilter : std::uint8_t { box = 0, bspline2 = 1 };
// "box" / "bspline2".
const char* pixel_filter_name(PixelFilter filter);
// false for any other text.
bool parse_pixel_filter(std::string_view text, PixelFilter* out);

// Throws std::invalid_argument when spp < 1.
RaySamples generate_ray_samples(const PointSet& points, const VisiblePoints& visible, int spp,
                                std::uint64_t seed, int screen_width_px, PixelFilter filter = PixelFilter::box);

// The offsets alone: sample s of point `point_index` inside a unit disc, pure function.
glm::vec2 unit_disc_sample(std::uint64_t seed, std::uint32_t point_index, int s);

// Sample s of pixel `pixel_index` (y * W + x) relative to the pixel's corner,
// distributed as `filter` centred on the pixel's centre (0.5, 0.5): box in
// [0, 1)^2, bspline2 in (-1, 2)^2. The full render's jitter, and the
// pixel-grid fovea's. Pure function; box gives the same offsets for a seed
// whatever other filters exist.
glm::vec2 pixel_jitter(std::uint64_t pixel_index, std::uint32_t sample, std::uint64_t seed,
                       PixelFilter filter = PixelFilter::box);

// Sample s of the pixel-grid point at screen position centre_px (a pixel
// centre) on a screen screen_width_px wide.
inline glm::vec2 pixel_sample_px(glm::vec2 centre_px, int s, std::uint64_t seed, int screen_width_px,
                                 PixelFilter filter = PixelFilter::box) {
  const glm::vec2 corner{float(int(centre_px.x)), float(int(centre_px.y))};
  const std::uint64_t pixel = std::uint64_t(int(centre_px.y)) * std::uint64_t(screen_width_px) + std::uint64_t(int(centre_px.x));
  return corner + pixel_jitter(pixel, std::uint32_t(s), seed, filter);
}

}  // namespace foveart::foveation
