// The one small display the cache fuzz targets and their seed corpora use: a
// mutated file must match this key to get past the header into the payload.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "foveation/interpolation_cache.hpp"
#include "foveation/point_set_cache.hpp"

namespace foveart::fuzz {

inline foveation::PointSetKey cache_key(int k) {
  foveation::PointSetKey key;
  key.display = foveation::DisplayModel::from_thesis(24, 16, 0.85);
  key.display.scale = 3.0;
  key.seed = 3;
  key.k = k;
  return key;
}

inline constexpr int kNeighbors = 4;

inline foveation::InterpOptions interp_options() {
  foveation::InterpOptions o;
  o.method = foveation::InterpMethod::msm;
  o.k = kNeighbors;
  return o;
}

// The fuzz input as a file (the loaders read files through a mapping).
inline std::filesystem::path input_file(const std::uint8_t* data, std::size_t size) {
  const auto path = std::filesystem::temp_directory_path() / ("foveart_fuzz_" + std::to_string(::getpid()) + ".bin");
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                               static_cast<std::streamsize>(size));
  return path;
}

}  // namespace foveart::fuzz
