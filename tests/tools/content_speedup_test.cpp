// content_speedup: full mode's per-tile cost weighted by the foveated points.
#include <content_speedup.hpp>

#include <gtest/gtest.h>

#include <vector>

using foveart::fovea::content_speedup;
using foveart::fovea::TileGrid;

TEST(ContentSpeedup, UniformCostGivesPixelsPerPoint) {
  const TileGrid g{128, 64, 64, 64, 2};  // two 64 x 64 tiles
  const std::vector<double> ms{2.0, 2.0};
  const std::vector<uint32_t> points{4096, 1024};  // 8192 px, 5120 points
  EXPECT_DOUBLE_EQ(content_speedup(g, ms, points), 8192.0 / 5120.0);
}

TEST(ContentSpeedup, PointsOnTheDearTileGainLess) {
  const TileGrid g{128, 64, 64, 64, 2};
  const std::vector<double> ms{1.0, 3.0};  // the right tile costs 3x per pixel
  // All points on the cheap tile: 4 ms of full frame / (1 ms x 1/2) = 8.
  EXPECT_DOUBLE_EQ(content_speedup(g, ms, std::vector<uint32_t>{2048, 0}), 8.0);
  // The same number of points on the dear tile: 4 / (3 x 1/2) = 8/3.
  EXPECT_DOUBLE_EQ(content_speedup(g, ms, std::vector<uint32_t>{0, 2048}), 4.0 / 1.5);
}

TEST(ContentSpeedup, EdgeTilesCountTheirOwnPixels) {
  const TileGrid g{100, 10, 64, 10, 2};  // 64 x 10 and a cut 36 x 10
  const std::vector<double> ms{6.4, 3.6};  // the same cost per pixel
  const std::vector<uint32_t> points{64, 36};  // one point per 10 pixels in both
  EXPECT_DOUBLE_EQ(content_speedup(g, ms, points), 10.0);
}

TEST(ContentSpeedup, MismatchedOrEmptyInputGivesZero) {
  const TileGrid g{128, 64, 64, 64, 2};
  EXPECT_EQ(content_speedup(g, std::vector<double>{1.0}, std::vector<uint32_t>{1, 1}), 0.0);
  EXPECT_EQ(content_speedup(g, std::vector<double>{1.0, 1.0}, std::vector<uint32_t>{0, 0}), 0.0);
  EXPECT_EQ(content_speedup(TileGrid{}, std::vector<double>{}, std::vector<uint32_t>{}), 0.0);
  const TileGrid too_few_rows{128, 64, 64, 64, 1};  // 2 tiles in a 1-wide grid: the second is off the image
  EXPECT_EQ(content_speedup(too_few_rows, std::vector<double>{1.0, 1.0}, std::vector<uint32_t>{1, 1}), 0.0);
}
