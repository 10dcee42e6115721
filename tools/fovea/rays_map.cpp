#include "rays_map.hpp"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

#include "foveation/srgb.hpp"

namespace foveart::fovea {

glm::vec3 rays_colour(unsigned rays, unsigned rays_per_point) {
  if (rays == 0) return kFilledRgb;
  const float t =
      rays_per_point <= 1 ? 1.0f : std::clamp(std::log2(float(rays)) / std::log2(float(rays_per_point)), 0.0f, 1.0f);
  return glm::mix(kOneRayRgb, kAllRaysRgb, t);
}

foveation::ImageRgb rays_map(const foveation::ViewTables& tables, const foveation::FrameHandOff& traced_frame,
                             const foveation::ImageRgb& frame, const foveation::DisplayTransform& display,
                             unsigned rays_per_point) {
  foveation::ImageRgb map;
  map.width_px = frame.width_px;
  map.height_px = frame.height_px;
  map.rgb.assign(frame.rgb.size(), 0.0f);
  // No points on the host (a device trace, or a frame planned for one): nothing to show.
  if (traced_frame.traced == nullptr) return map;
  const foveation::TracedPoints& traced = *traced_frame.traced;
  const std::size_t points = tables.points.size();
  if (traced.colors.rgba.size() != points || traced.rays_cast.size() != points) return map;
  const foveation::NeighborTable& neighbors = tables.neighbors;
  for (int y = 0; y < frame.height_px; ++y) {
    for (int x = 0; x < frame.width_px; ++x) {
      const std::size_t pixel =
          traced_frame.mapping.canvas_index(std::size_t(x), std::size_t(y), std::size_t(neighbors.width_px()));
      const std::uint32_t point = foveation::nearest_valid_point(neighbors, pixel, traced.colors.rgba.data());
      const glm::vec3 colour =
          point == foveation::kNoValidPoint ? kNoPointRgb : rays_colour(traced.rays_cast[point], rays_per_point);
      const float* radiance = frame.at(x, y);
      const glm::vec3 shown = display.apply(glm::vec3(radiance[0], radiance[1], radiance[2]));
      const float luma = foveation::rec709_luminance(shown.r, shown.g, shown.b);
      const glm::vec3 shaded = colour * (0.3f + 0.7f * luma);
      float* out = map.at(x, y);
      out[0] = shaded.r;
      out[1] = shaded.g;
      out[2] = shaded.b;
    }
  }
  return map;
}

}  // namespace foveart::fovea
