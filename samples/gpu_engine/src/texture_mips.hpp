// A texture's mip chain for the ray footprint's level of detail (scene_data.glsl
// sample_texture_lod): each level a 2x2 box filter of the one above, in linear
// values, down to 1x1. Level 0 is the texture itself and is not repeated here.
#pragma once

#include <engine/scene.hpp>

#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace foveart::gpu_engine {

struct MipLevel {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<glm::vec4> texels;  // row-major, top row first
};

// Levels 1.. of `texture`: level k is max(1, w >> k) x max(1, h >> k), each texel the mean of
// the (up to) 2x2 texels above it (an odd last row or column folds into the texel before it).
std::vector<MipLevel> box_mip_chain(const engine::Texture& texture);

// Levels a w x h texture has in all: 1 + floor(log2(max(w, h))).
uint32_t mip_level_count(uint32_t width, uint32_t height);

}  // namespace foveart::gpu_engine
