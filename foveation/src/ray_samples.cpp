// Per-point jittered ray samples (thesis 4.2: same seed every frame).
#include "foveation/ray_samples.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "hash.hpp"

namespace foveart::foveation {

glm::vec2 unit_disc_sample(std::uint64_t seed, std::uint32_t point_index, int s) {
  const std::uint64_t key = detail::mix64(seed ^ detail::mix64((std::uint64_t(point_index) << 16) ^
                                                               std::uint64_t(s)));
  const double u = detail::unit_double(key);
  const double v = detail::unit_double(detail::mix64(key));
  // Uniform by area: r = sqrt(u), theta = 2 pi v.
  const double r = std::sqrt(u);
  const double theta = 2.0 * std::numbers::pi * v;
  return {float(r * std::cos(theta)), float(r * std::sin(theta))};
}

const char* pixel_filter_name(PixelFilter filter) {
  return filter == PixelFilter::bspline2 ? "bspline2" : "box";
}

bool parse_pixel_filter(std::string_view text, PixelFilter* out) {
  if (text == "box") *out = PixelFilter::box;
  else if (text == "bspline2") *out = PixelFilter::bspline2;
  else return false;
  return true;
}

namespace {

// Two uniforms in [0, 1) from 64 bits, 24 bits each: exactly representable, strictly below 1.
glm::vec2 unit_pair(std::uint64_t h) {
  return {float(h >> 40) * 0x1.0p-24f, float((h >> 16) & 0xFFFFFFu) * 0x1.0p-24f};
}

}  // namespace

// The box's uniform offset; bspline2: the sum of three independent uniforms
// minus 1 is the quadratic B-spline on (-1, 2), centred on 0.5 (Unser 1999).
glm::vec2 pixel_jitter(std::uint64_t pixel_index, std::uint32_t sample, std::uint64_t seed, PixelFilter filter) {
  const std::uint64_t h =
      detail::mix64(pixel_index * 0x100000001B3ull ^ detail::mix64(std::uint64_t(sample) + (seed << 32)));
  if (filter == PixelFilter::box) return unit_pair(h);
  const std::uint64_t h2 = detail::mix64(h), h3 = detail::mix64(h2);
  return unit_pair(h) + unit_pair(h2) + unit_pair(h3) - glm::vec2(1.0f);
}

RaySamples generate_ray_samples(const PointSet& points, const VisiblePoints& visible, int spp,
                                std::uint64_t seed, int screen_width_px, PixelFilter filter) {
  if (spp < 1) throw std::invalid_argument("rays per point must be >= 1");
  RaySamples out;
  out.spp = spp;
  out.sample_px.resize(visible.size() * std::size_t(spp));
  out.point_index.resize(visible.size() * std::size_t(spp));
  for (std::size_t v = 0; v < visible.size(); ++v) {
    const std::uint32_t p = visible.point_index[v];
    const float radius = points.radius_px[p];
    for (int s = 0; s < spp; ++s) {
      const std::size_t o = v * std::size_t(spp) + std::size_t(s);
      out.sample_px[o] = points.on_pixel_grid(p) ? pixel_sample_px(visible.screen_px[v], s, seed, screen_width_px, filter)
                                                 : visible.screen_px[v] + unit_disc_sample(seed, p, s) * radius;
      out.point_index[o] = p;
    }
  }
  return out;
}

}  // namespace foveart::foveation
