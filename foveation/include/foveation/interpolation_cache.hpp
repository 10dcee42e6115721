// On-disk cache of interpolation tables, in the style of point_set_cache.hpp.
//
// A file holds a header (magic, format version, the full parameter string the
// weights depend on — display, seed, point set checksum, method, k, shape,
// constant term, thresholds, precision — payload size, XXH3 of the payload)
// followed by the weights and the gather layout (palettes, 1-byte taps). A file that is missing, truncated, corrupt, of
// another format version or for other parameters is rejected with a message
// saying which, and load_or_build rebuilds it. Never serves wrong weights.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "foveation/interpolation_table.hpp"
#include "foveation/point_set_cache.hpp"

namespace foveart::foveation {

inline constexpr std::uint32_t kInterpCacheFormatVersion = 2;  // 2: tile-order weights + gather layout

// Every parameter the table depends on, as one exact string (hex floats).
std::string interpolation_cache_params(const PointSetKey& key, const PointSet& points, const InterpOptions& options,
                                       WeightPrecision precision);

std::filesystem::path interpolation_cache_path(const std::filesystem::path& dir, const std::string& params,
                                               const InterpOptions& options);

// Atomic write (temp file + rename). Returns an error message, empty on success.
std::string save_interpolation_table(const std::filesystem::path& file, const std::string& params,
                                     const InterpolationTable& table);
// nullopt with *error set when missing or rejected.
std::optional<InterpolationTable> load_interpolation_table(const std::filesystem::path& file, const std::string& params,
                                                           std::string* error);

struct CachedTable {
  InterpolationTable table;
  bool from_cache = false;
  double ms = 0.0;  // load or build
};
// Loads from `cache_dir` or builds (and stores) the table; rejections go to `log`.
CachedTable load_or_build_interpolation_table(const std::optional<std::filesystem::path>& cache_dir,
                                              const PointSetKey& key, const PointSet& points,
                                              const NeighborTable& neighbors, const InterpOptions& options,
                                              Executor& executor,
                                              std::optional<WeightPrecision> precision = std::nullopt,
                                              const ProgressFn& progress = {}, const LogFn& log = {});

}  // namespace foveart::foveation
