// Replay: record -> replay -> identical samples; original timing (on a virtual
// clock, tests/common/manual_clock.hpp); end of trace. Real time only bounds the
// waits for the end of a trace replayed as fast as possible (a guard: running
// out of it fails the test).
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "gaze_provider/backends.h"
#include "gaze_provider/simulator.h"
#include "gaze_provider/trace_csv.h"
#include "manual_clock.hpp"

using namespace foveart::gaze;
using namespace std::chrono_literals;

namespace {
std::string temp_path(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string("foveart_gaze_") + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::vector<GazeSample> drain_until_ended(GazeProvider& p, std::chrono::seconds limit) {
  std::vector<GazeSample> all, buf(512);
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    const std::size_t n = p.read_raw(buf);
    all.insert(all.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
    if (n == 0) {
      if (p.status().state == ProviderState::ended && p.read_raw(buf) == 0) break;
      std::this_thread::sleep_for(1ms);
    }
  }
  return all;
}
}  // namespace

TEST(Replay, RecordReplayRoundTripIsIdentical) {
  const std::string path = temp_path("roundtrip.csv");
  std::vector<GazeSample> recorded;
  {
    GazeSimulator sim(SimConfig{.seed = 77});
    std::ofstream out(path);
    TraceWriter w(out);
    for (int i = 0; i < 6000; ++i) {  // 50 s of gaze: more than the raw ring holds
      GazeSample s = sim.next();
      s.host_time_ns = s.device_time_ns + 250'000;
      recorded.push_back(s);
      w.write(s);
    }
  }
  ProviderOptions options;
  options.replay.original_timing = false;
  options.raw_ring_capacity = 256;  // forces the lossless wait path
  CreateResult created = create_gaze_provider("replay:" + path, options);
  ASSERT_TRUE(created) << created.error;
  std::string error;
  ASSERT_TRUE(created.provider->start(&error)) << error;
  const std::vector<GazeSample> replayed = drain_until_ended(*created.provider, 20s);
  created.provider->stop();
  EXPECT_EQ(created.provider->status().state, ProviderState::ended);
  EXPECT_NE(created.provider->status().reason_string().find("end of trace"), std::string::npos);
  ASSERT_EQ(replayed.size(), recorded.size());
  for (std::size_t i = 0; i < recorded.size(); ++i) {
    const GazeSample &a = recorded[i], &b = replayed[i];
    ASSERT_EQ(a.device_time_ns, b.device_time_ns) << i;
    ASSERT_EQ(a.host_time_ns, b.host_time_ns) << i;
    ASSERT_EQ(a.frame_id, b.frame_id);
    ASSERT_EQ(a.valid, b.valid);
    ASSERT_EQ(a.eye_state, b.eye_state);
    ASSERT_EQ(a.confidence, b.confidence);
    ASSERT_EQ(0, std::memcmp(&a.combined_direction, &b.combined_direction, sizeof(Vec3f))) << i;
    ASSERT_EQ(0, std::memcmp(&a.left.direction, &b.left.direction, sizeof(Vec3f))) << i;
    EXPECT_EQ(b.source, GazeSourceKind::replay);
  }
  std::remove(path.c_str());
}

// Played at its original timing, a trace's samples arrive exactly as far apart in
// host time as they were recorded in device time, from the start on: 31 samples
// at 100 Hz over 300 ms of virtual time, none early, then the end of the trace.
TEST(Replay, OriginalTimingFollowsTheTrace) {
  const std::string path = temp_path("timing.csv");
  {
    std::ofstream out(path);
    out << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
    for (int i = 0; i < 31; ++i) out << i * 10000 << ',' << i << ",1,0,0,1\n";  // 300 ms at 100 Hz
  }
  auto clock = std::make_shared<foveart::test::ManualClock>();
  ProviderOptions options;
  options.clock = clock;
  CreateResult created = create_gaze_provider("replay:" + path, options);
  ASSERT_TRUE(created) << created.error;
  foveart::test::ReleaseAtExit release{*clock};
  GazeProvider& p = *created.provider;
  EXPECT_NEAR(p.nominal_rate_hz(), 100.0, 1e-6);
  const std::int64_t start = clock->now_ns();
  std::string error;
  ASSERT_TRUE(p.start(&error)) << error;
  std::vector<GazeSample> samples, buf(64);
  auto ended = [&] { return p.status().state == ProviderState::ended; };
  // Half way between two samples, only those due so far have come.
  for (int half_steps = 1; half_steps <= 61; half_steps += 2) {
    ASSERT_TRUE(clock->run_until(start + half_steps * 5'000'000, ended));
    const std::size_t n = p.read_raw(buf);
    samples.insert(samples.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
    ASSERT_EQ(samples.size(), std::size_t(half_steps / 2 + 1)) << "at " << half_steps * 5 << " ms";
  }
  ASSERT_TRUE(clock->run_until(start + 1'000'000'000, ended));
  EXPECT_EQ(p.status().state, ProviderState::ended);
  EXPECT_EQ(p.read_raw(buf), 0u);
  ASSERT_EQ(samples.size(), 31u);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(samples[i].host_time_ns - start, samples[i].device_time_ns - samples[0].device_time_ns) << i;
  }
  p.stop();
  std::remove(path.c_str());
}

TEST(Replay, BadTracesFailCreationWithLineNumbers) {
  const std::string path = temp_path("bad.csv");
  {
    std::ofstream out(path);
    out << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,0,1,0,0,1\n8333,1,1,0,oops,1\n";
  }
  CreateResult created = create_gaze_provider("replay:" + path);
  EXPECT_FALSE(created);
  EXPECT_NE(created.error.find(path + ":3: column 5 'gaze_y'"), std::string::npos) << created.error;
  {
    std::ofstream out(path);
    out << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
  }
  created = create_gaze_provider("replay:" + path);
  EXPECT_FALSE(created);
  EXPECT_NE(created.error.find("no samples"), std::string::npos) << created.error;
  std::remove(path.c_str());
}
