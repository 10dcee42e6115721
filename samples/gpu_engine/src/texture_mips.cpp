#include "texture_mips.hpp"

#include <algorithm>

namespace foveart::gpu_engine {
namespace {

// The next level of `above` (w x h): each texel the mean of the texels of `above` it covers.
MipLevel half_level(const std::vector<glm::vec4>& above, uint32_t w, uint32_t h) {
  MipLevel level;
  level.width = std::max(1u, w / 2);
  level.height = std::max(1u, h / 2);
  level.texels.resize(size_t{level.width} * level.height);
  for (uint32_t y = 0; y < level.height; ++y) {
    // Rows 2y, 2y + 1, and 2y + 2 for the last row of an odd height.
    const uint32_t y1 = (y + 1 == level.height) ? h : std::min(h, 2 * y + 2);
    for (uint32_t x = 0; x < level.width; ++x) {
      const uint32_t x1 = (x + 1 == level.width) ? w : std::min(w, 2 * x + 2);
      glm::vec4 sum(0.0f);
      for (uint32_t sy = 2 * y; sy < y1; ++sy)
        for (uint32_t sx = 2 * x; sx < x1; ++sx) sum += above[size_t{sy} * w + sx];
      level.texels[size_t{y} * level.width + x] = sum / static_cast<float>((y1 - 2 * y) * (x1 - 2 * x));
    }
  }
  return level;
}

}  // namespace

uint32_t mip_level_count(uint32_t width, uint32_t height) {
  uint32_t levels = 1;
  for (uint32_t side = std::max(width, height); side > 1; side /= 2) ++levels;
  return levels;
}

std::vector<MipLevel> box_mip_chain(const engine::Texture& texture) {
  std::vector<MipLevel> levels;
  if (texture.width == 0 || texture.height == 0 || texture.texels.size() < size_t{texture.width} * texture.height)
    return levels;
  levels.reserve(mip_level_count(texture.width, texture.height) - 1);  // `above` points into it
  const std::vector<glm::vec4>* above = &texture.texels;
  uint32_t w = texture.width, h = texture.height;
  while (w > 1 || h > 1) {
    levels.push_back(half_level(*above, w, h));
    above = &levels.back().texels;
    w = levels.back().width;
    h = levels.back().height;
  }
  return levels;
}

}  // namespace foveart::gpu_engine
