// PNG images for the tools (stb_image / stb_image_write), over the one image
// type of FoveaRT (foveation::ImageRgb). Errors are returned as messages naming
// the file; nothing throws.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "foveation/image.hpp"

namespace foveart::toolkit {

// What the float values of an image are.
enum class PngValues : std::uint8_t {
  linear,   // linear RGB: sRGB-encoded (IEC 61966-2-1) on write, decoded on read
  display,  // display values in [0, 1], stored as they are (x 255)
};

// 8-bit RGB PNG of `image` (values clamped to [0, 1]).
std::string write_png(const std::string& path, const foveation::ImageRgb& image, PngValues values);
// Any stb-readable image as RGB floats. Empty string on success.
std::string read_image(const std::string& path, PngValues values, foveation::ImageRgb* out);
// 8-bit grey, RGB or RGBA PNG as given (channels 1, 3 or 4).
std::string write_png_u8(const std::string& path, int width, int height, int channels,
                         const std::vector<std::uint8_t>& pixels);

}  // namespace foveart::toolkit
