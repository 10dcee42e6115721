// A float RGB image, row-major, 3 interleaved channels (linear or display
// values, as the caller chooses). The interpolation gather writes these.
#pragma once

#include <cstddef>
#include <vector>

namespace foveart::foveation {

struct ImageRgb {
  int width_px = 0;
  int height_px = 0;
  std::vector<float> rgb;  // width * height * 3

  ImageRgb() = default;
  ImageRgb(int width, int height) : width_px(width), height_px(height), rgb(std::size_t(width) * std::size_t(height) * 3) {}
  std::size_t pixel_count() const { return std::size_t(width_px) * std::size_t(height_px); }
  float* at(int x, int y) { return rgb.data() + (std::size_t(y) * std::size_t(width_px) + std::size_t(x)) * 3; }
  const float* at(int x, int y) const { return rgb.data() + (std::size_t(y) * std::size_t(width_px) + std::size_t(x)) * 3; }
};

}  // namespace foveart::foveation
