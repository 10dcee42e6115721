// libFuzzer: the sample engine's glTF loader on arbitrary .gltf text (embedded
// buffers as data: URIs reach the accessor reader without other files).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "engine/gltf_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = std::filesystem::temp_directory_path() / ("foveart_fuzz_" + std::to_string(::getpid()) + ".gltf");
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                               static_cast<std::streamsize>(size));
  const auto result = foveart::engine::load_gltf(path.string());
  if (!result.ok() && result.error.empty()) __builtin_trap();  // a failure always says why
  return 0;
}
