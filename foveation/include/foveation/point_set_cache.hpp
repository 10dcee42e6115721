// On-disk cache of the point set and its neighbour table.
//
// Versioned binary files with a header that records every parameter the data
// depends on, the payload size and an XXH3 checksum. A file that is truncated,
// corrupt, from another format version or for other parameters is rejected with
// a message saying which; callers then rebuild. Never serves wrong points.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "foveation/display_model.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"

namespace foveart::foveation {

// 4: points stored in Hilbert order (3: Morton order).
inline constexpr std::uint32_t kCacheFormatVersion = 4;

// Everything a cached point set / table depends on.
struct PointSetKey {
  DisplayModel display;
  std::uint64_t seed = 1;
  int k = 0;  // 0 for the point set file itself
};

std::filesystem::path point_set_cache_path(const std::filesystem::path& dir, const PointSetKey& key);
std::filesystem::path neighbor_table_cache_path(const std::filesystem::path& dir, const PointSetKey& key);

// Writes atomically (temp file + rename). Returns an error message, empty on success.
std::string save_point_set(const std::filesystem::path& file, const PointSetKey& key, const PointSet& points);
std::string save_neighbor_table(const std::filesystem::path& file, const PointSetKey& key,
                                const NeighborTable& table);

// nullopt with *error set when missing or rejected.
std::optional<PointSet> load_point_set(const std::filesystem::path& file, const PointSetKey& key,
                                       std::string* error);
std::optional<NeighborTable> load_neighbor_table(const std::filesystem::path& file,
                                                 const PointSetKey& key, std::string* error);

// The usual path: load both from `dir` or build (and store) what is missing or
// rejected. Rejections are reported through `log`; `built_*` tell what was rebuilt.
struct FoveationTables {
  PointSet points;
  NeighborTable neighbors;
  bool points_from_cache = false;
  bool neighbors_from_cache = false;
  double generation_ms = 0.0;  // point set (build or load)
  double table_ms = 0.0;       // neighbour table (build or load)
};
using LogFn = std::function<void(const std::string&)>;
FoveationTables load_or_build_tables(const std::optional<std::filesystem::path>& cache_dir,
                                     const PointSetKey& key, Executor& executor, const ProgressFn& progress = {},
                                     const LogFn& log = {});

}  // namespace foveart::foveation
