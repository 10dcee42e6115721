// The temporal histories the foveation tests compare: the product's two modes
// with a history (image, rays) and the building blocks' variants the lab
// measures (an image history that restarts when the view moves, a render
// cache kept through restarts), made for a FoveatedView's history argument.
#pragma once

#include <memory>

#include "foveation/image_history.hpp"
#include "foveation/ray_history.hpp"
#include "foveation/view_settings.hpp"
#include "foveation/view_tables.hpp"

namespace foveart::foveation::test {

enum class HistoryKind { restart_on_view_change, reproject, ray_cache, ray_cache_kept };

// The product's mode a kind is a variant of.
inline TemporalMode mode_of(HistoryKind kind) {
  return kind == HistoryKind::ray_cache || kind == HistoryKind::ray_cache_kept ? TemporalMode::rays
                                                                                : TemporalMode::image;
}

// The history of `kind` for a view of `settings` over `tables` (which must outlive it).
inline std::unique_ptr<TemporalHistory> make_history(HistoryKind kind, const ViewTables& tables,
                                                                const ViewSettings& settings) {
  const TemporalOptions blend = settings.blend_options();
  switch (kind) {
    case HistoryKind::restart_on_view_change:
      return std::make_unique<ImageHistory>(tables.neighbors, blend, /*reproject=*/false);
    case HistoryKind::reproject:
      return std::make_unique<ImageHistory>(tables.neighbors, blend, /*reproject=*/true);
    case HistoryKind::ray_cache:
    case HistoryKind::ray_cache_kept:
      break;
  }
  return std::make_unique<RayHistory>(
      tables, blend,
      RayHistoryOptions{settings.pixel_filter, settings.ray_cache_max_age_frames,
                                   kind == HistoryKind::ray_cache_kept});
}

}  // namespace foveart::foveation::test
