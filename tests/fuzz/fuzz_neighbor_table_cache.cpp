// libFuzzer: the neighbour table cache loader on arbitrary file contents.
#include <cstddef>
#include <cstdint>

#include "fuzz_cache_key.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string error;
  const auto table = foveart::foveation::load_neighbor_table(foveart::fuzz::input_file(data, size),
                                                             foveart::fuzz::cache_key(foveart::fuzz::kNeighbors), &error);
  if (!table && error.empty()) __builtin_trap();
  return 0;
}
