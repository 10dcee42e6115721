// libFuzzer: the point set cache loader on arbitrary file contents.
#include <cstddef>
#include <cstdint>

#include "fuzz_cache_key.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string error;
  const auto points = foveart::foveation::load_point_set(foveart::fuzz::input_file(data, size),
                                                         foveart::fuzz::cache_key(foveart::fuzz::kNeighbors), &error);
  if (!points && error.empty()) __builtin_trap();  // a rejection always says why
  return 0;
}
