// PNG images for the tools (stb_image / stb_image_write), over the one image
// type of FoveaRT (foveation::ImageRgb). Each returns false and *error naming
// the file on failure; nothing throws.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "foveation/display_transform.hpp"
#include "foveation/image.hpp"

namespace foveart::toolkit {

// What the float values of an image are.
enum class PngValues : std::uint8_t {
  linear,   // linear RGB: sRGB-encoded (IEC 61966-2-1) on write, decoded on read
  display,  // display values in [0, 1], stored as they are (x 255)
};

// 8-bit RGB PNG of `image` (values clamped to [0, 1]).
[[nodiscard]] bool write_png(const std::string& path, const foveation::ImageRgb& image, PngValues values,
                             std::string* error);
// 8-bit sRGB PNG of linear radiance through a display transform (exposure,
// tone-mapping curve): what the layer would show of it.
[[nodiscard]] bool write_png(const std::string& path, const foveation::ImageRgb& image,
                             const foveation::DisplayTransform& display, std::string* error);
// Any stb-readable image as RGB floats.
[[nodiscard]] bool read_image(const std::string& path, PngValues values, foveation::ImageRgb* out, std::string* error);
// 8-bit grey, RGB or RGBA PNG as given (channels 1, 3 or 4).
[[nodiscard]] bool write_png_u8(const std::string& path, int width, int height, int channels,
                                const std::vector<std::uint8_t>& pixels, std::string* error);

}  // namespace foveart::toolkit
