// The one executor: every index exactly once, from several callers at once,
// nested calls inline, exceptions back to the caller, and no thread for one.
#include <atomic>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "foveation/executor.hpp"

namespace foveart::foveation {
namespace {

TEST(Executor, EveryIndexExactlyOnceOverManyRounds) {
  Executor executor(3);
  EXPECT_EQ(executor.thread_count(), 3u);
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> hits(257);
    executor.parallel_for(hits.size(), [&](std::size_t i) { hits[i].fetch_add(1); });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "round " << round << " i " << i;
  }
}

TEST(Executor, WorkerSlotsAreUniqueAmongConcurrentRunners) {
  Executor executor(4);
  std::vector<std::atomic<int>> busy(executor.thread_count());
  std::atomic<bool> clash{false};
  executor.parallel_for(400, [&](std::size_t, unsigned worker) {
    ASSERT_LT(worker, executor.thread_count());
    if (busy[worker].fetch_add(1) != 0) clash = true;
    std::this_thread::yield();
    busy[worker].fetch_sub(1);
  });
  EXPECT_FALSE(clash.load());
}

TEST(Executor, ChunksCoverTheRangeOnce) {
  Executor executor(2);
  std::vector<std::atomic<int>> hits(1001);
  executor.parallel_chunks(hits.size(), 64, [&](std::size_t first, std::size_t last, unsigned) {
    EXPECT_LE(last - first, 64u);
    for (std::size_t i = first; i < last; ++i) hits[i].fetch_add(1);
  });
  for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
}

TEST(Executor, OneThreadRunsOnTheCallerAndZeroTasksReturn) {
  Executor single(1);
  EXPECT_EQ(single.thread_count(), 1u);
  const auto caller = std::this_thread::get_id();
  int calls = 0;
  single.parallel_for(0, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  single.parallel_for(5, [&](std::size_t, unsigned worker) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    EXPECT_EQ(worker, 0u);
    ++calls;
  });
  EXPECT_EQ(calls, 5);
}

TEST(Executor, MoreThreadsThanTheMostIsRefusedWithoutStartingAny) {
  EXPECT_THROW(Executor(kMaxExecutorThreads + 1), std::invalid_argument);
  EXPECT_THROW(Executor(100000), std::invalid_argument);
  Executor all_cores(0);
  EXPECT_GE(all_cores.thread_count(), 1u);
  EXPECT_LE(all_cores.thread_count(), kMaxExecutorThreads);
}

TEST(Executor, SeveralCallersShareTheWorkers) {
  Executor executor(3);
  std::vector<std::atomic<int>> a(300), b(300);
  std::thread other([&] {
    for (int r = 0; r < 20; ++r) executor.parallel_for(a.size(), [&](std::size_t i) { a[i].fetch_add(1); });
  });
  for (int r = 0; r < 20; ++r) executor.parallel_for(b.size(), [&](std::size_t i) { b[i].fetch_add(1); });
  other.join();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].load(), 20);
    ASSERT_EQ(b[i].load(), 20);
  }
}

TEST(Executor, NestedCallsRunInline) {
  Executor executor(2);
  std::atomic<int> inner{0};
  executor.parallel_for(8, [&](std::size_t) {
    const auto self = std::this_thread::get_id();
    executor.parallel_for(4, [&](std::size_t) {
      EXPECT_EQ(std::this_thread::get_id(), self);
      inner.fetch_add(1);
    });
  });
  EXPECT_EQ(inner.load(), 32);
}

TEST(Executor, FirstExceptionReachesTheCallerAfterEveryIndexEnded) {
  Executor executor(3);
  std::atomic<int> running{0};
  EXPECT_THROW(executor.parallel_for(100,
                                     [&](std::size_t i) {
                                       running.fetch_add(1);
                                       if (i == 10) throw std::runtime_error("index 10");
                                       running.fetch_sub(1);
                                     }),
               std::runtime_error);
  EXPECT_EQ(running.load(), 1);  // only the thrower never came back; nobody is still inside
  std::atomic<int> after{0};
  executor.parallel_for(10, [&](std::size_t) { after.fetch_add(1); });  // still usable
  EXPECT_EQ(after.load(), 10);
}

}  // namespace
}  // namespace foveart::foveation
