#include "toolkit/image_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include <stb_image.h>
#include <stb_image_write.h>

#include "foveation/srgb.hpp"

namespace foveart::toolkit {


std::string write_png_u8(const std::string& path, int width, int height, int channels,
                         const std::vector<std::uint8_t>& pixels) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3 && channels != 4) ||
      pixels.size() != std::size_t(width) * std::size_t(height) * std::size_t(channels)) {
    return "cannot write " + path + ": image size does not match its pixels";
  }
  errno = 0;
  if (stbi_write_png(path.c_str(), width, height, channels, pixels.data(), width * channels) == 0) {
    return "cannot write " + path + (errno != 0 ? std::string(": ") + std::strerror(errno) : std::string());
  }
  return {};
}

std::string write_png_linear(const std::string& path, const ImageRgb& image) {
  std::vector<std::uint8_t> px(image.rgb.size());
  for (std::size_t i = 0; i < px.size(); ++i) {
    px[i] = foveation::encode_srgb8(image.rgb[i]);
  }
  return write_png_u8(path, image.width, image.height, 3, px);
}

std::string read_image_linear(const std::string& path, ImageRgb* out) {
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 3);
  if (data == nullptr) {
    const char* why = stbi_failure_reason();
    return "cannot read image " + path + ": " + (why ? why : "unknown error");
  }
  out->width = w;
  out->height = h;
  out->rgb.resize(std::size_t(w) * std::size_t(h) * 3);
  for (std::size_t i = 0; i < out->rgb.size(); ++i) out->rgb[i] = foveation::srgb_to_linear(float(data[i]) / 255.0f);
  stbi_image_free(data);
  return {};
}

}  // namespace foveart::toolkit
