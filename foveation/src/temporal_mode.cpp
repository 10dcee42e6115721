#include "foveation/temporal_mode.hpp"

#include "foveation/view_settings.hpp"

namespace foveart::foveation {

const char* temporal_mode_name(TemporalMode mode) {
  switch (mode) {
    case TemporalMode::off: return "off";
    case TemporalMode::image: return "image";
    case TemporalMode::rays: return "rays";
  }
  return "off";
}

bool parse_temporal_mode(std::string_view text, TemporalMode* out) {
  for (TemporalMode m : {TemporalMode::off, TemporalMode::image, TemporalMode::rays}) {
    if (text == temporal_mode_name(m)) {
      *out = m;
      return true;
    }
  }
  return false;
}

ViewSettings temporal_view_settings(TemporalMode mode, int rays_per_point, std::uint64_t sample_seed) {
  ViewSettings v;
  v.rays_per_point = rays_per_point;
  v.sample_seed = sample_seed;
  v.temporal = mode;
  v.new_jitter_each_frame = mode != TemporalMode::off;  // a history converges over new samples
  // The render cache filters its rays into the pixels around them: the B-spline spreads each one
  // smoothly, which is what brings its flicker under the goal; an image history keeps the box.
  v.pixel_filter = mode == TemporalMode::rays ? PixelFilter::bspline2 : PixelFilter::box;
  return v;
}

}  // namespace foveart::foveation
