#include "foveation/rgba8.hpp"


namespace foveart::foveation {

void encode_rgba8(const ImageRgb& image, bool srgb, const DisplayTransform& display, std::uint8_t* out,
                  Executor& executor) {
  const std::size_t width = std::size_t(image.width_px);
  executor.parallel_chunks(std::size_t(image.height_px), 64, [&](std::size_t y0, std::size_t y1, unsigned) {
    display.encode_rgba8(image.rgb.data() + y0 * width * 3, (y1 - y0) * width, srgb, out + y0 * width * 4);
  });
}

}  // namespace foveart::foveation
