// PNG images for the tools (stb_image / stb_image_write). Errors are returned
// as messages naming the file; nothing throws.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace foveart::toolkit {

// Linear RGB float image, row-major, 3 floats per pixel.
struct ImageRgb {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;
};

// Writes 8-bit sRGB-encoded PNG from linear RGB (clamped to [0, 1]).
std::string write_png_linear(const std::string& path, const ImageRgb& image);
// Writes 8-bit grey or RGB PNG as given (channels 1 or 3).
std::string write_png_u8(const std::string& path, int width, int height, int channels,
                         const std::vector<std::uint8_t>& pixels);
// Reads a PNG (or any stb-readable image) to linear RGB. Empty string on success.
std::string read_image_linear(const std::string& path, ImageRgb* out);

}  // namespace foveart::toolkit
