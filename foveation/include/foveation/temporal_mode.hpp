// The one temporal choice of a foveated frame, as the layer's config, the extension and
// the tools name it: no history, an image history reprojected each frame, or the traced
// rays kept in a render cache. Each mode fixes the TAA, its history, the per-frame jitter
// and the pixel filter; nothing else chooses them for the product.
#pragma once

#include <cstdint>
#include <string_view>

#include "foveation/foveated_view.hpp"

namespace foveart::foveation {

enum class TemporalMode : std::uint8_t {
  off,    // each frame from its own rays (thesis 4.2), box pixel filter
  image,  // TAA on an image history, reprojected with the head (Karis 2014), box pixel filter
  rays,   // TAA on a render cache of the traced rays (Walter et al. 1999), B-spline pixel filter
};

// "off" | "image" | "rays".
const char* temporal_mode_name(TemporalMode mode);
// False (and *out unchanged) for any other text.
bool parse_temporal_mode(std::string_view text, TemporalMode* out);

// The view settings of a mode at rays_per_point jittered rays per point.
ViewSettings temporal_view_settings(TemporalMode mode, int rays_per_point, std::uint64_t sample_seed);

}  // namespace foveart::foveation
