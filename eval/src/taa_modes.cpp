#include <eval/taa_modes.hpp>

#include <foveation/image_history.hpp>
#include <foveation/ray_history.hpp>
#include <foveation/temporal_mode.hpp>

#include <algorithm>
#include <sstream>
#include <utility>

namespace foveart::eval {

bool is_taa_mode(const std::string& name) {
  return name == "off" || name == "restart" || name == "reproject" || name == "cache" || name == "cache-kept";
}

bool parse_taa_modes(const std::string& text, std::vector<std::string>* out, std::string* error) {
  const auto fail = [&](std::string message) {
    *error = std::move(message);
    return false;
  };
  out->clear();
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!is_taa_mode(item)) return fail("--taa: '" + item + "' is not off, restart, reproject, cache or cache-kept");
    if (std::find(out->begin(), out->end(), item) != out->end()) return fail("--taa: '" + item + "' given twice");
    out->push_back(item);
  }
  if (out->empty() || text.back() == ',')
    return fail("--taa: expected off, restart, reproject, cache, cache-kept or a list of them");
  return true;
}

const char* taa_mode_of(foveation::TemporalMode mode) {
  switch (mode) {
    case foveation::TemporalMode::off: return "off";
    case foveation::TemporalMode::image: return "reproject";
    case foveation::TemporalMode::rays: return "cache";
  }
  return "off";
}

foveation::ViewSettings taa_view_settings(const std::string& mode, int rays_per_point, std::uint64_t seed,
                                          foveation::PixelFilter pixel_filter, bool taa_mean_while_young) {
  // The product's mode (the layer's "temporal") first, then the lab's own variations of it.
  const foveation::TemporalMode product = mode == "off"                           ? foveation::TemporalMode::off
                                          : mode == "cache" || mode == "cache-kept" ? foveation::TemporalMode::rays
                                                                                    : foveation::TemporalMode::image;
  foveation::ViewSettings vs = foveation::temporal_view_settings(product, rays_per_point, seed);
  vs.pixel_filter = pixel_filter;  // the lab measures every filter under every mode
  vs.temporal_options.mean_while_young = taa_mean_while_young;
  return vs;
}

std::unique_ptr<foveation::FoveatedView> make_taa_view(std::shared_ptr<const foveation::ViewTables> tables,
                                                       const std::string& mode, int rays_per_point, std::uint64_t seed,
                                                       foveation::PixelFilter pixel_filter, bool taa_mean_while_young) {
  const foveation::ViewSettings vs = taa_view_settings(mode, rays_per_point, seed, pixel_filter, taa_mean_while_young);
  std::unique_ptr<foveation::TemporalHistory> history;  // null: the product's mode
  if (mode == "restart") {
    history = std::make_unique<foveation::ImageHistory>(tables->neighbors, vs.blend_options(), /*reproject=*/false);
  } else if (mode == "cache-kept") {
    history = std::make_unique<foveation::RayHistory>(
        *tables, vs.blend_options(),
        foveation::RayHistoryOptions{vs.pixel_filter, vs.ray_cache_max_age_frames, /*keep_through_restarts=*/true});
  }
  return std::make_unique<foveation::FoveatedView>(std::move(tables), vs, std::move(history));
}

}  // namespace foveart::eval
