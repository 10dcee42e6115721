// Everything a view's frames read that depends only on the display: the point
// set, the k nearest points of every canvas pixel and the method's weights,
// loaded from the cache directory or built once and shared, immutable, by the
// views (both eyes) of that display.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>

#include "foveation/executor.hpp"
#include "foveation/interpolation_table.hpp"
#include "foveation/interpolation_weights.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_levels.hpp"
#include "foveation/point_set.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/ray_trace.h"

namespace foveart::foveation {

struct ViewTables {
  PointSetKey key;
  PointSet points;
  NeighborTable neighbors;
  InterpolationTable interpolation;
  bool from_cache = false;  // all three loaded from the cache directory
  double load_ms = 0.0;     // load or build, all three

  // The point set's levels for content-aware density (point_levels.hpp), built on first
  // use: views that thin nothing never pay for them. Any thread.
  const PointLevels& levels(Executor& executor) const {
    std::call_once(lazy_levels_->once, [&] { lazy_levels_->levels = build_point_levels(points, executor); });
    return lazy_levels_->levels;
  }

 private:
  struct LazyLevels {
    std::once_flag once;
    PointLevels levels;
  };
  std::shared_ptr<LazyLevels> lazy_levels_ = std::make_shared<LazyLevels>();
};

// The display whose tables fit a submitted view: its size and its horizontal
// span (DisplayModel::from_fov), from the view's float angles. The layer and
// `fovea render --fov` both call this, so they build the same point set.
DisplayModel display_of_view(const FoveartEyeView& view);

// Neighbours per canvas pixel the tables keep for a method: k, and at least 4
// for NN, so that a pixel whose nearest point was not traced (beyond the
// visible margin) falls back to the next nearest traced one.
int neighbor_count(const InterpOptions& interpolation);

// Loads the tables of `key.display` from `cache_dir` (nullopt: no cache) or
// builds and stores them. key.k is set from the method. Rejected cache files go
// to `log`; build errors throw.
std::shared_ptr<const ViewTables> load_view_tables(const std::optional<std::filesystem::path>& cache_dir,
                                                   PointSetKey key, const InterpOptions& interpolation,
                                                   Executor& executor,
                                                   std::optional<WeightPrecision> precision = std::nullopt,
                                                   const ProgressFn& progress = {}, const LogFn& log = {});

}  // namespace foveart::foveation
