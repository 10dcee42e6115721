// The one temporal choice of a foveated frame, as the layer's config, the extension and
// the tools name it: no history, an image history reprojected each frame, or the traced
// rays kept in a render cache. Each mode fixes the history, the per-frame jitter and the
// pixel filter (temporal_view_settings in view_settings.hpp); nothing else chooses them
// for the product.
#pragma once

#include <cstdint>
#include <string_view>


namespace foveart::foveation {

enum class TemporalMode : std::uint8_t {
  off,    // each frame from its own rays (thesis 4.2), box pixel filter
  image,  // an image history, reprojected with the head and blended (Karis 2014), box pixel filter
  rays,   // a render cache of the traced rays (Walter et al. 1999), blended alike, B-spline pixel filter
};

// "off" | "image" | "rays".
const char* temporal_mode_name(TemporalMode mode);
// False (and *out unchanged) for any other text.
bool parse_temporal_mode(std::string_view text, TemporalMode* out);


}  // namespace foveart::foveation
