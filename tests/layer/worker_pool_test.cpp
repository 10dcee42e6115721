// The worker pool runs every index exactly once, on several threads, again and again.
#include <atomic>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "worker_pool.hpp"

namespace foveart::layer {
namespace {

TEST(WorkerPool, EveryIndexExactlyOnceOverManyRounds) {
  WorkerPool pool(3);
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> hits(257);
    pool.parallel_for(hits.size(), [&](std::size_t i) { hits[i].fetch_add(1); });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "round " << round << " i " << i;
  }
}

TEST(WorkerPool, ZeroTasksReturnsAndOneThreadWorks) {
  WorkerPool single(1);
  EXPECT_EQ(single.size(), 1u);
  int calls = 0;
  single.parallel_for(0, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  single.parallel_for(5, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls, 5);
}

}  // namespace
}  // namespace foveart::layer
