// libFuzzer: the interpolation table cache loader on arbitrary file contents,
// against the parameters of the seed's point set.
#include <cstddef>
#include <cstdint>

#include "foveation/interpolation_weights.hpp"
#include "fuzz_cache_key.hpp"

namespace {
const std::string& params() {
  static const std::string p = [] {
    const auto key = foveart::fuzz::cache_key(foveart::fuzz::kNeighbors);
    const auto points = foveart::foveation::generate_point_set(key.display, key.seed);
    auto options = foveart::fuzz::interp_options();
    options.shape = foveart::foveation::effective_shape(options);  // as load_or_build_interpolation_table keys it
    return foveart::foveation::interpolation_cache_params(key, points, options,
                                                          foveart::foveation::kDefaultWeightPrecision);
  }();
  return p;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string error;
  const auto table = foveart::foveation::load_interpolation_table(foveart::fuzz::input_file(data, size), params(), &error);
  if (!table && error.empty()) __builtin_trap();
  return 0;
}
