// libFuzzer: the layer's config parser. Whatever the text, it warns and uses
// defaults; it never throws (an exception here would cross xrCreateInstance).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  foveart::layer::ConfigResult result;
  try {
    foveart::layer::apply_config_text(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json",
                                      "hello_xr", &result);
  } catch (...) {
    __builtin_trap();
  }
  return 0;
}
