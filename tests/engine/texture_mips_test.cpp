// The GPU engine's mip chains (samples/gpu_engine/src/texture_mips.hpp): each level half the
// one above down to 1x1, each texel the mean of the texels it covers, odd edges folded in.
#include "texture_mips.hpp"

#include <gtest/gtest.h>

namespace {

using foveart::gpu_engine::box_mip_chain;
using foveart::gpu_engine::mip_level_count;

TEST(TextureMips, LevelsHalveDownToOneTexel) {
  EXPECT_EQ(mip_level_count(1, 1), 1u);
  EXPECT_EQ(mip_level_count(256, 256), 9u);
  EXPECT_EQ(mip_level_count(5, 3), 3u);
  foveart::engine::Texture t;
  t.width = 256;
  t.height = 64;
  t.texels.assign(std::size_t{t.width} * t.height, glm::vec4(0.5f));
  const auto chain = box_mip_chain(t);
  ASSERT_EQ(chain.size(), 8u);
  EXPECT_EQ(chain.front().width, 128u);
  EXPECT_EQ(chain.front().height, 32u);
  EXPECT_EQ(chain.back().width, 1u);
  EXPECT_EQ(chain.back().height, 1u);
  EXPECT_EQ(chain.back().texels.at(0), glm::vec4(0.5f)) << "a flat texture stays flat";
}

TEST(TextureMips, EachTexelIsTheMeanOfWhatItCovers) {
  foveart::engine::Texture t;  // 5 x 3: texel (x, y) = x + 10 y
  t.width = 5;
  t.height = 3;
  for (uint32_t y = 0; y < 3; ++y)
    for (uint32_t x = 0; x < 5; ++x) t.texels.push_back(glm::vec4(float(x + 10 * y)));
  const auto chain = box_mip_chain(t);
  ASSERT_EQ(chain.size(), 2u);
  ASSERT_EQ(chain[0].width, 2u);
  ASSERT_EQ(chain[0].height, 1u);
  // Level 1, texel 0: columns 0-1, rows 0-2 (the odd last row folded in); texel 1: columns 2-4.
  EXPECT_FLOAT_EQ(chain[0].texels[0].x, (0 + 1 + 10 + 11 + 20 + 21) / 6.0f);
  EXPECT_FLOAT_EQ(chain[0].texels[1].x, (2 + 3 + 4 + 12 + 13 + 14 + 22 + 23 + 24) / 9.0f);
  EXPECT_FLOAT_EQ(chain[1].texels[0].x, (chain[0].texels[0].x + chain[0].texels[1].x) / 2.0f);
}

TEST(TextureMips, NoChainForAnEmptyTexture) {
  EXPECT_TRUE(box_mip_chain(foveart::engine::Texture{}).empty());
}

}  // namespace
