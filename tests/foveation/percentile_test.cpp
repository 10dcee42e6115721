// foveation/percentile.hpp: nearest rank (Hyndman & Fan's definition 1), so a
// reported p99 is always one of the measured samples.
#include "foveation/percentile.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace foveart::foveation {
namespace {

TEST(Percentile, NearestRankOfOneToHundred) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // unsorted on purpose
  EXPECT_EQ(percentile(v, 50), 50.0);
  EXPECT_EQ(percentile(v, 95), 95.0);
  EXPECT_EQ(percentile(v, 99), 99.0);
  EXPECT_EQ(percentile(v, 100), 100.0);
  EXPECT_EQ(percentile(v, 0), 1.0);  // rank 0 is the smallest sample
}

TEST(Percentile, SmallSamplesTakeTheRankAtOrAbove) {
  // Three samples: p50 is the second (rank ceil(1.5) = 2), p99 the third, never an interpolation.
  EXPECT_EQ(percentile(std::vector<float>{3.0f, 1.0f, 2.0f}, 50), 2.0f);
  EXPECT_EQ(percentile(std::vector<float>{3.0f, 1.0f, 2.0f}, 99), 3.0f);
  EXPECT_EQ(percentile(std::vector<float>{4.0f, 1.0f}, 50), 1.0f);
  EXPECT_EQ(percentile(std::vector<float>{7.5f}, 99), 7.5f);
}

TEST(Percentile, NoSamplesGiveZero) {
  EXPECT_EQ(percentile(std::vector<double>{}, 50), 0.0);
  EXPECT_EQ(percentile(std::vector<float>{}, 99), 0.0f);
}

}  // namespace
}  // namespace foveart::foveation
