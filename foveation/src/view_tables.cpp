#include "foveation/view_tables.hpp"

#include <algorithm>
#include <chrono>
#include <numbers>

#include "foveation/interpolation_cache.hpp"

namespace foveart::foveation {

DisplayModel display_of_view(const FoveartEyeView& view) {
  const double span_rad = double(view.angle_right_rad) - double(view.angle_left_rad);
  return DisplayModel::from_fov(int(view.width_px), int(view.height_px), span_rad * 180.0 / std::numbers::pi);
}

int neighbor_count(const InterpOptions& interpolation) {
  return interpolation.method == InterpMethod::nearest ? std::max(4, interpolation.k) : interpolation.k;
}

std::shared_ptr<const ViewTables> load_view_tables(const std::optional<std::filesystem::path>& cache_dir,
                                                   PointSetKey key, const InterpOptions& interpolation,
                                                   Executor& executor, std::optional<WeightPrecision> precision,
                                                   const ProgressFn& progress, const LogFn& log) {
  const auto t0 = std::chrono::steady_clock::now();
  // The point set and neighbour table are ~90% of a first build, the weights the rest.
  auto part = [&](double lo, double hi) -> ProgressFn {
    if (!progress) return {};
    return [=, &progress](double f) { progress(lo + (hi - lo) * f); };
  };
  key.k = neighbor_count(interpolation);
  auto out = std::make_shared<ViewTables>();
  out->key = key;
  FoveationTables tables = load_or_build_tables(cache_dir, key, executor, part(0.0, 0.9), log);
  out->points = std::move(tables.points);
  out->neighbors = std::move(tables.neighbors);
  CachedTable interp = load_or_build_interpolation_table(cache_dir, key, out->points, out->neighbors, interpolation,
                                                         executor, precision, part(0.9, 1.0), log);
  out->interpolation = std::move(interp.table);
  out->from_cache = tables.points_from_cache && tables.neighbors_from_cache && interp.from_cache;
  out->load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace foveart::foveation
