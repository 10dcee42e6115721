#include "foveation/rgba8.hpp"

#include <algorithm>
#include <cmath>

#include "foveation/srgb.hpp"

namespace foveart::foveation {

void encode_rgba8(const ImageRgb& image, bool srgb, std::uint8_t* out, Executor& executor) {
  const std::size_t width = std::size_t(image.width_px);
  executor.parallel_chunks(std::size_t(image.height_px), 64, [&](std::size_t y0, std::size_t y1, unsigned) {
    for (std::size_t i = y0 * width; i < y1 * width; ++i) {
      const float* p = image.rgb.data() + i * 3;
      std::uint8_t* o = out + i * 4;
      for (int c = 0; c < 3; ++c) {
        o[c] = srgb ? encode_srgb8(p[c]) : std::uint8_t(std::lround(std::clamp(p[c], 0.0f, 1.0f) * 255.0f));
      }
      o[3] = 255;
    }
  });
}

}  // namespace foveart::foveation
