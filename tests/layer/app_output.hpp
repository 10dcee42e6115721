// What a test reads back from a hello_foveated run: the JSON object it prints
// last with --json (after the layer's log lines) and the simulated runtime's
// captured frames (FOVEART_SIM_CAPTURE_DIR), read as 8-bit RGB.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

namespace foveart::layer::test {

// The JSON object from the output's first line that opens with '{' to its end
// (the layer logs before it; the object's own inner lines are indented); null
// when there is none, discarded (is_discarded()) when it does not parse.
inline nlohmann::json trailing_json(const std::string& output) {
  const auto brace = output.find("\n{");
  if (brace == std::string::npos) return nullptr;
  return nlohmann::json::parse(output.substr(brace + 1), nullptr, false);
}

// The simulated runtime's capture of frame `index`, eye "left" or "right", in `dir`.
inline std::filesystem::path captured_frame(const std::filesystem::path& dir, int index, const char* eye) {
  char name[64];
  std::snprintf(name, sizeof(name), "frame_%06d_%s.png", index, eye);
  return dir / name;
}

// An 8-bit RGB image; width and height 0 when the file could not be read.
struct Rgb8 {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

inline Rgb8 load_rgb(const std::filesystem::path& png) {
  Rgb8 img;
  int channels = 0;
  unsigned char* data = stbi_load(png.c_str(), &img.width, &img.height, &channels, 3);
  if (data == nullptr) return img;
  img.rgb.assign(data, data + std::size_t(img.width) * std::size_t(img.height) * 3);
  stbi_image_free(data);
  return img;
}

}  // namespace foveart::layer::test
