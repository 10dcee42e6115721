// SPSC ring and seqlock history: order, capacity, and consistency under concurrency.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "gaze_provider/seqlock.h"
#include "gaze_provider/spsc_ring.h"

using namespace foveart::gaze;

TEST(SpscRing, FifoAndFull) {
  SpscRing<int> ring(3);  // rounded up to 4
  EXPECT_EQ(ring.capacity(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
  EXPECT_FALSE(ring.try_push(99)) << "a full ring must refuse, not overwrite";
  int v = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.try_pop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(ring.try_pop(v));
}

TEST(SpscRing, ProducerConsumerThreadsKeepOrder) {
  SpscRing<std::uint64_t> ring(64);
  constexpr std::uint64_t kCount = 200000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount;)
      if (ring.try_push(i)) ++i;
      else std::this_thread::yield();
  });
  std::uint64_t expected = 0;
  bool ordered = true;
  std::uint64_t buf[32];
  while (expected < kCount) {
    const std::size_t n = ring.pop_into(buf);
    for (std::size_t i = 0; i < n; ++i) ordered &= buf[i] == expected++;
    if (n == 0) std::this_thread::yield();
  }
  producer.join();
  EXPECT_TRUE(ordered);
  EXPECT_EQ(ring.size(), 0u);
}

namespace {
struct Words {
  std::uint64_t w[12];
};
}  // namespace

TEST(SeqlockHistory, ReadersNeverSeeTornValues) {
  SeqlockHistory<Words, 8> history;
  std::atomic<bool> done{false};
  constexpr std::uint64_t kWrites = 100000;
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= kWrites; ++i) {
      Words v;
      for (auto& w : v.w) w = i;
      history.publish(v);
    }
    done = true;
  });
  std::atomic<std::uint64_t> torn{0}, reads{0};
  auto reader = [&] {
    Words out[4];
    while (!done.load()) {
      const std::size_t n = history.read_latest(out, 4);
      for (std::size_t k = 0; k < n; ++k) {
        for (auto w : out[k].w) torn += w != out[k].w[0];
        if (k > 0) torn += out[k].w[0] + 1 != out[k - 1].w[0];  // newest first, consecutive
      }
      reads += n;
    }
  };
  std::thread r1(reader), r2(reader);
  writer.join();
  r1.join();
  r2.join();
  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(history.count(), kWrites);
  Words last[1];
  ASSERT_EQ(history.read_latest(last, 1), 1u);
  EXPECT_EQ(last[0].w[5], kWrites);
}
