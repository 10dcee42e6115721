#include "foveation/rgba8.hpp"

#include <cmath>

namespace foveart::foveation {

void encode_rgba8(const ImageRgb& image, bool srgb, const DisplayTransform& display, std::uint8_t* out,
                  Executor& executor) {
  const std::size_t width = std::size_t(image.width_px);
  executor.parallel_chunks(std::size_t(image.height_px), 64, [&](std::size_t y0, std::size_t y1, unsigned) {
    for (std::size_t i = y0 * width; i < y1 * width; ++i) {
      const float* p = image.rgb.data() + i * 3;
      const glm::vec3 radiance(p[0], p[1], p[2]);
      std::uint8_t* o = out + i * 4;
      if (srgb) {
        const glm::u8vec3 b = display.srgb8(radiance);
        o[0] = b.r, o[1] = b.g, o[2] = b.b;
      } else {
        const glm::vec3 c = display.apply(radiance);
        for (int k = 0; k < 3; ++k) o[k] = std::uint8_t(std::lround(c[k] * 255.0f));
      }
      o[3] = 255;
    }
  });
}

}  // namespace foveart::foveation
