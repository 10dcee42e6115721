// The threaded simulated provider: rate, readers on other threads, stop.
//
// Timing policy: every test runs the provider on a virtual host clock
// (tests/common/manual_clock.hpp) that moves only when the test moves it, so
// pacing is checked exactly and no check depends on how the machine schedules
// threads. How punctual the sampling thread is on the real clock is a
// measurement, not a pass/fail check: bench/gaze_bench.cpp.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <future>
#include <memory>
#include <thread>
#include <vector>

#include "gaze_provider/backends.h"
#include "gaze_provider/trace_stats.h"
#include "manual_clock.hpp"

using namespace foveart::gaze;
using foveart::test::ManualClock;
using foveart::test::ReleaseAtExit;

namespace {
constexpr std::int64_t kMs = 1'000'000;

ProviderOptions on(const std::shared_ptr<ManualClock>& clock) {
  ProviderOptions o;
  o.clock = clock;
  return o;
}

void drain(GazeProvider& p, std::vector<GazeSample>& into) {
  std::vector<GazeSample> buf(256);
  for (std::size_t n; (n = p.read_raw(buf)) > 0;) into.insert(into.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
}
}  // namespace

// Two seconds of virtual time at 120 Hz: sample i comes at exactly start +
// round(i * 1e9 / 120) ns, host and device time alike, none early, none late,
// none dropped: frames 0..240.
TEST(SimProvider, Holds120HzOverTwoSeconds) {
  auto clock = std::make_shared<ManualClock>();
  CreateResult created = create_gaze_provider("sim:5", on(clock));
  ASSERT_TRUE(created) << created.error;
  ReleaseAtExit release{*clock};
  GazeProvider& p = *created.provider;
  EXPECT_EQ(p.status().state, ProviderState::stopped);
  const std::int64_t start = clock->now_ns();
  std::string error;
  ASSERT_TRUE(p.start(&error)) << error;
  std::vector<GazeSample> all;
  for (int step = 1; step <= 200; ++step) {  // read every 10 ms, as a consumer would
    ASSERT_TRUE(clock->run_until(start + step * 10 * kMs))
        << "the sampling thread did not settle by " << step * 10 << " ms";
    drain(p, all);
  }

  ASSERT_EQ(all.size(), 241u) << "120 Hz over 2 s of virtual time: frames 0..240";
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::int64_t due = start + std::llround(double(i) * 1e9 / 120.0);
    ASSERT_EQ(all[i].host_time_ns, due) << "sample " << i;
    ASSERT_EQ(all[i].device_time_ns, due) << "sample " << i;
    ASSERT_EQ(all[i].frame_id, i);
  }
  const TraceStats st = compute_stats(all, {}, true);
  EXPECT_NEAR(st.rate_hz, 120.0, 1e-6);
  EXPECT_EQ(st.dropped, 0u) << "frame ids are consecutive: the ring never overflowed";
  EXPECT_EQ(p.status().raw_dropped, 0u);
  EXPECT_EQ(p.status().state, ProviderState::streaming);
}

// Readers on two threads while the raw consumer reads and virtual time moves
// 10 ms at a time: every sample they see is consistent and none goes back in time.
TEST(SimProvider, ReadersOnOtherThreadsSeeConsistentSamples) {
  auto clock = std::make_shared<ManualClock>();
  CreateResult created = create_gaze_provider("sim:9", on(clock));
  ASSERT_TRUE(created) << created.error;
  ReleaseAtExit release{*clock};
  GazeProvider& p = *created.provider;
  const std::int64_t start = clock->now_ns();
  std::string error;
  ASSERT_TRUE(p.start(&error)) << error;
  std::atomic<bool> done{false};
  std::atomic<int> bad{0}, reads{0};
  auto reader = [&] {
    std::int64_t last_device = 0;
    while (!done.load()) {
      if (auto s = p.latest()) {
        bad += s->device_time_ns < last_device;  // never goes back in time
        last_device = s->device_time_ns;
        if (s->valid) bad += std::abs(length(s->combined_direction) - 1.0) > 1e-4;
        ++reads;
      }
      if (auto s = p.sample_at(clock->now_ns() + 20'000'000)) bad += s->valid && !is_finite(s->combined_direction);
      (void)p.status();
    }
  };
  std::thread r1(reader), r2(reader);
  std::vector<GazeSample> buf(64);
  bool settled = true, overlapped = true;
  for (int i = 1; i <= 50 && settled && overlapped; ++i) {  // the single raw consumer, concurrently
    settled = clock->run_until(start + i * 10 * kMs);
    p.read_raw(buf);
    // The readers read at each step, between the sampling thread's samples.
    const int before = reads.load();
    overlapped = ManualClock::eventually([&] { return reads.load() >= before + 2; });
  }
  done = true;
  r1.join();
  r2.join();
  ASSERT_TRUE(settled && overlapped);
  EXPECT_EQ(p.status().state, ProviderState::streaming);
  clock->release();
  p.stop();
  EXPECT_EQ(p.status().state, ProviderState::stopped);
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GE(reads.load(), 100);
  EXPECT_EQ(p.status().samples, 61u) << "frames 0..60 in 500 ms of virtual time";
}

// The sampling thread never sleeps more than 50 ms at a time (a 1 Hz source,
// so it could): stop() needs at most that much time to pass. Start again after.
TEST(SimProvider, StopIsBoundedAndRestartable) {
  auto clock = std::make_shared<ManualClock>();
  ProviderOptions options = on(clock);
  options.sim.rate_hz = 1.0;
  CreateResult created = create_gaze_provider("sim", options);
  ASSERT_TRUE(created) << created.error;
  ReleaseAtExit release{*clock};
  std::string error;
  for (int round = 0; round < 2; ++round) {
    SCOPED_TRACE(round);
    ASSERT_TRUE(created.provider->start(&error)) << error;
    ASSERT_TRUE(clock->run_until(clock->now_ns() + 1'500 * kMs));
    EXPECT_TRUE(created.provider->latest().has_value());
    EXPECT_GT(clock->longest_sleep_ns(), 0);
    EXPECT_LE(clock->longest_sleep_ns(), 50 * kMs) << "a sleep that long holds stop() up as long";
    // stop() on another thread returns once the current sleep (<= 50 ms) ends.
    auto stopped = std::async(std::launch::async, [&] { created.provider->stop(); });
    auto stop_returned = [&] { return stopped.wait_for(std::chrono::seconds(0)) == std::future_status::ready; };
    bool settled = true, returned = false;
    for (int i = 0; i < 1000 && settled && !returned; ++i) {
      settled = clock->settle(stop_returned);
      returned = stop_returned();
      if (!returned) clock->advance_to(clock->now_ns() + 50 * kMs);
    }
    if (!returned) clock->release();  // lets the pending stop() return before the failure below ends the test
    ASSERT_TRUE(settled && returned);
    EXPECT_EQ(created.provider->status().state, ProviderState::stopped);
  }
}
