// The lab's TAA modes (fovea-eval --taa): the product's temporal modes
// (foveation/temporal_mode.hpp) and the lab's variations of them, and the view
// settings of each.
#pragma once

#include <foveation/foveated_view.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/temporal_mode.hpp>
#include <foveation/view_settings.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace foveart::eval {

// "off", "restart" (TaaHistory::restart_on_view_change, the TAA before
// reprojection), "reproject" (TaaHistory::reproject), "cache"
// (TaaHistory::ray_cache) or "cache-kept" (the same, its rays kept through a
// saccade or a blink).
bool is_taa_mode(const std::string& name);
// The TAA mode of the product's temporal mode: "off", "reproject" (image) or "cache" (rays).
const char* taa_mode_of(foveation::TemporalMode mode);
// "off,restart,reproject" -> the modes; false and *error naming the bad entry.
[[nodiscard]] bool parse_taa_modes(const std::string& text, std::vector<std::string>* out, std::string* error);
// The view settings of a foveated frame with this TAA mode at equal rays: TAA
// off keeps one jitter seed (the thesis's choice); TAA draws new jitter each
// frame, which it accumulates; taa_mean_while_young: TemporalOptions::mean_while_young.
foveation::ViewSettings taa_view_settings(const std::string& taa_mode, int rays_per_point, std::uint64_t seed,
                                          foveation::PixelFilter pixel_filter, bool taa_mean_while_young);
// The foveated view of that mode over `tables`: the product's history, or the
// lab's variant of it (restart, cache-kept).
std::unique_ptr<foveation::FoveatedView> make_taa_view(std::shared_ptr<const foveation::ViewTables> tables,
                                                       const std::string& taa_mode, int rays_per_point,
                                                       std::uint64_t seed, foveation::PixelFilter pixel_filter,
                                                       bool taa_mean_while_young);


}  // namespace foveart::eval
