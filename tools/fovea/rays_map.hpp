// What a foveated frame traced, as a picture (`fovea render --out`'s _rays.png):
// each pixel takes the colour of its nearest coloured point, by the rays that
// point cast this frame, shaded by the frame's own luminance so the scene stays
// recognisable. Shows where content-aware density thinned points and where it
// cast fewer rays per point (docs/content_density.md).
#pragma once

#include <glm/vec3.hpp>

#include "foveation/display_transform.hpp"
#include "foveation/frame_stages.hpp"
#include "foveation/image.hpp"
#include "foveation/view_tables.hpp"

namespace foveart::fovea {

inline constexpr glm::vec3 kOneRayRgb{0.10f, 0.20f, 0.85f};   // a point that cast one ray
inline constexpr glm::vec3 kAllRaysRgb{1.00f, 0.80f, 0.05f};  // ... all rays_per_point
inline constexpr glm::vec3 kFilledRgb{0.55f, 0.55f, 0.55f};   // filled from its parents, no ray of its own
inline constexpr glm::vec3 kNoPointRgb{0.0f, 0.0f, 0.0f};     // no coloured point in reach

// The colour of a point that cast `rays` of rays_per_point: kOneRayRgb to kAllRaysRgb on a
// log scale (all rays_per_point when it is 1); kFilledRgb for 0.
glm::vec3 rays_colour(unsigned rays, unsigned rays_per_point);

// The map over the frame's screen, in display values [0, 1]: rays_colour of each pixel's
// nearest point with a colour (the neighbour table's order), times 0.3 + 0.7 × the display
// luminance of `frame` (the foveated image, radiance) there.
foveation::ImageRgb rays_map(const foveation::ViewTables& tables, const foveation::FrameHandOff& traced_frame,
                             const foveation::ImageRgb& frame, const foveation::DisplayTransform& display,
                             unsigned rays_per_point);

}  // namespace foveart::fovea
