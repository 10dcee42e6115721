// FOVE backend against the fake client library (fake_fove/fake_fove_client.cpp):
// error-code mapping, blinks, dropouts, a disconnect and a reconnect.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <thread>

#include "gaze_provider/backends.h"

using namespace foveart::gaze;
using namespace std::chrono_literals;

namespace {

using ConfigureFn = void (*)(std::uint64_t, int, int);
using FrameFn = std::int64_t (*)();

// The test opens the fake library itself to reach its controls; the backend's
// dlopen() of the same path returns the same instance.
class FakeFove : public ::testing::Test {
 protected:
  void SetUp() override {
    lib_ = dlopen(FAKE_FOVE_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(lib_, nullptr) << dlerror();
    configure_ = reinterpret_cast<ConfigureFn>(dlsym(lib_, "fake_fove_configure"));
    frame_ = reinterpret_cast<FrameFn>(dlsym(lib_, "fake_fove_frame"));
    ASSERT_TRUE(configure_ && frame_);
    options_.fove.library_path = FAKE_FOVE_LIBRARY;
  }
  void TearDown() override {
    if (lib_) dlclose(lib_);
  }
  void* lib_ = nullptr;
  ConfigureFn configure_ = nullptr;
  FrameFn frame_ = nullptr;
  ProviderOptions options_;
};

}  // namespace

TEST_F(FakeFove, ScriptedStreamMapsErrorCodes) {
  configure_(2000, 0, 0);  // 2 ms per eye frame: the 140-frame script runs in ~0.3 s
  CreateResult created = create_gaze_provider("fove", options_);
  ASSERT_TRUE(created) << created.error;
  GazeProvider& p = *created.provider;
  EXPECT_EQ(p.source(), GazeSourceKind::fove);
  std::string error;
  ASSERT_TRUE(p.start(&error)) << error;
  // Until the provider has published the script's last frame (id 1139); 20 s is
  // a guard: running out of it fails the checks below.
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  auto last_frame_in = [&] {
    const auto latest = p.latest();
    return latest && latest->frame_id >= 1139;
  };
  while (!last_frame_in() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
  const ProviderStatus running = p.status();
  p.stop();

  std::vector<GazeSample> all(4096);
  all.resize(p.read_raw(all));
  std::map<std::uint64_t, GazeSample> by_id;
  for (const GazeSample& s : all) by_id[s.frame_id] = s;
  ASSERT_GE(by_id.size(), 120u);

  for (std::uint64_t k = 0; k < 140; ++k) {
    const std::uint64_t id = 1000 + k;
    if (k >= 100 && k < 115) {
      EXPECT_EQ(by_id.count(id), 0u) << "no frames while the service is gone, k=" << k;
      continue;
    }
    ASSERT_EQ(by_id.count(id), 1u) << "k=" << k;
    const GazeSample& s = by_id[id];
    EXPECT_EQ(s.device_time_ns, (5'000'000 + std::llround(double(k) * 1e6 / 120.0)) * 1000) << "k=" << k;
    if (k >= 30 && k < 36) {  // blink: Data_Unreliable -> invalid
      EXPECT_FALSE(s.valid) << "k=" << k;
      EXPECT_EQ(s.eye_state, EyeState::closed);
    } else if (k >= 60 && k < 66) {  // Data_LowAccuracy -> valid, low confidence
      EXPECT_TRUE(s.valid) << "k=" << k;
      EXPECT_FLOAT_EQ(s.confidence, 0.3f);
    } else if (k >= 66 && k < 96) {  // dropout
      EXPECT_FALSE(s.valid) << "k=" << k;
      EXPECT_EQ(s.eye_state, EyeState::not_detected);
    } else {
      EXPECT_TRUE(s.valid) << "k=" << k;
      EXPECT_FLOAT_EQ(s.confidence, 1.0f);
      EXPECT_NEAR(to_yaw_pitch_deg(s.combined_direction).yaw_deg, 0.1 * double(k), 1e-3);
      EXPECT_TRUE(s.left.valid && s.right.valid);
    }
  }
  EXPECT_EQ(running.disconnects, 1u) << "one disconnect, then a reconnect";
  EXPECT_EQ(running.state, ProviderState::streaming) << running.reason.data();

  // The filter chain over the same samples: the blink is bridged (held), the 250 ms
  // dropout is held for 200 ms and then lost.
  FilterChain chain;
  int held = 0, lost = 0;
  for (const auto& [id, s] : by_id) {
    const GazeSample f = chain.process(s);
    const std::uint64_t k = id - 1000;
    if (k >= 30 && k < 36) {
      EXPECT_TRUE(f.valid && f.held) << "blink bridged, k=" << k;
    }
    held += f.held;
    lost += f.lost;
  }
  EXPECT_EQ(held, 6 + 24);
  EXPECT_EQ(lost, 6);
}

TEST_F(FakeFove, DisconnectIsReportedWithReason) {
  configure_(2000, 0, 1);  // service lost at frame 100 and never back
  CreateResult created = create_gaze_provider("fove", options_);
  ASSERT_TRUE(created) << created.error;
  std::string error;
  ASSERT_TRUE(created.provider->start(&error)) << error;
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (created.provider->status().state != ProviderState::disconnected && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(5ms);
  const ProviderStatus st = created.provider->status();
  created.provider->stop();
  EXPECT_EQ(st.state, ProviderState::disconnected);
  EXPECT_NE(st.reason_string().find("Connect_NotConnected"), std::string::npos) << st.reason_string();
  const auto late = created.provider->sample_at(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                    std::chrono::steady_clock::now().time_since_epoch())
                                                    .count() +
                                                1'000'000'000);
  ASSERT_TRUE(late.has_value());
  EXPECT_FALSE(late->valid) << "a second after the last frame the gaze is stale";
}

TEST_F(FakeFove, CreateFailuresAreErrorsNotCrashes) {
  configure_(2000, 1, 0);
  CreateResult created = create_gaze_provider("fove", options_);
  EXPECT_FALSE(created);
  EXPECT_NE(created.error.find("fove_createHeadset"), std::string::npos) << created.error;
  EXPECT_NE(created.error.find("Connect_NotConnected"), std::string::npos) << created.error;

  ProviderOptions missing;
  missing.fove.library_path = "/nonexistent/libFoveClient.so";
  created = create_gaze_provider("fove", missing);
  EXPECT_FALSE(created);
  EXPECT_NE(created.error.find("/nonexistent/libFoveClient.so"), std::string::npos) << created.error;

  ProviderOptions not_fove;
  not_fove.fove.library_path = "libm.so.6";  // loads, but is no FOVE client
  created = create_gaze_provider("fove", not_fove);
  EXPECT_FALSE(created);
  EXPECT_NE(created.error.find("fove_createHeadset"), std::string::npos) << created.error;
}
