// Each filter stage on synthetic signals: step, ramp, noise, saccade, blink.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "gaze_provider/filters.h"

#include "tracker_period.hpp"

using namespace foveart::gaze;

namespace {

GazeSample sample_at_yaw(double yaw_deg, std::int64_t i, bool valid = true) {
  GazeSample s;
  s.device_time_ns = i * kPeriodNs;
  s.host_time_ns = s.device_time_ns;
  s.frame_id = std::uint64_t(i);
  s.valid = valid;
  s.eye_state = valid ? EyeState::open : EyeState::closed;
  s.combined_direction = from_yaw_pitch_deg(yaw_deg, 0.0);
  return s;
}
}  // namespace

TEST(OneEuro, StepConvergesWithoutOvershoot) {
  OneEuroFilter f;
  double prev = 0.0, out = 0.0;
  bool monotonic = true;
  for (int i = 0; i < 240; ++i) {
    const double in = i < 120 ? 0.0 : 10.0;
    out = f.filter(in, i * kPeriodNs);
    if (i >= 120) monotonic &= out >= prev - 1e-12;
    EXPECT_LE(out, 10.0 + 1e-9);
    prev = out;
  }
  EXPECT_TRUE(monotonic);
  EXPECT_NEAR(out, 10.0, 0.05) << "settles within 1 s after the step";
}

TEST(OneEuro, RampLagShrinksWithBeta) {
  auto lag_for = [](double beta) {
    OneEuroConfig c;
    c.beta = beta;
    OneEuroFilter f(c);
    double lag = 0.0;
    for (int i = 0; i < 240; ++i) {
      const double in = 20.0 * i / 120.0;  // 20 deg/s smooth pursuit
      lag = in - f.filter(in, i * kPeriodNs);
    }
    return lag;
  };
  const double lag_default = lag_for(OneEuroConfig{}.beta);
  const double lag_static = lag_for(0.0);
  EXPECT_GT(lag_default, 0.0);
  EXPECT_LT(lag_default, 0.4) << "default tuning: lag on a 20 deg/s ramp";
  EXPECT_LT(lag_default, 0.5 * lag_static) << "speed-adaptive cutoff must cut the lag";
}

TEST(OneEuro, SuppressesFixationNoise) {
  OneEuroFilter f;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  double sum_in = 0, sum_out = 0;
  int n = 0;
  for (int i = 0; i < 1200; ++i) {
    const double in = noise(rng);
    const double out = f.filter(in, i * kPeriodNs);
    if (i < 120) continue;
    sum_in += in * in;
    sum_out += out * out;
    ++n;
  }
  const double rms_in = std::sqrt(sum_in / n), rms_out = std::sqrt(sum_out / n);
  EXPECT_LT(rms_out, rms_in / 2.5) << "in " << rms_in << " out " << rms_out;
}

TEST(OneEuro, RestartsAfterAGap) {
  OneEuroFilter f;
  for (int i = 0; i < 10; ++i) f.filter(0.0, i * kPeriodNs);
  EXPECT_DOUBLE_EQ(f.filter(15.0, 10 * kPeriodNs + 200'000'000), 15.0) << "a blink-long gap resets the state";
}

TEST(SaccadeDetector, StepSaccadeDetectedOnceNearOnset) {
  SaccadeDetector d;
  int onsets = 0, onset_index = -1;
  for (int i = 0; i < 120; ++i) {
    // 10 deg minimum-jerk saccade starting at sample 60, 43 ms long.
    const double t = (i - 60) * kPeriodNs * 1e-9 / 0.043;
    const double tau = std::clamp(t, 0.0, 1.0);
    const double yaw = 10.0 * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
    const auto r = d.update(from_yaw_pitch_deg(yaw, 0.0), i * kPeriodNs);
    if (r.onset) {
      ++onsets;
      onset_index = i;
    }
  }
  EXPECT_EQ(onsets, 1);
  EXPECT_GE(onset_index, 60);
  EXPECT_LE(onset_index, 63);
}

TEST(SaccadeDetector, PursuitAndNoiseAreNotSaccades) {
  SaccadeConfig c;
  SaccadeDetector d(c);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.15);
  int onsets = 0;
  for (int i = 0; i < 1200; ++i) {
    const double yaw = 30.0 * i / 120.0 * 0.5 + noise(rng);  // 15 deg/s pursuit + noise
    onsets += d.update(from_yaw_pitch_deg(yaw, noise(rng)), i * kPeriodNs).onset;
  }
  EXPECT_EQ(onsets, 0);
  SaccadeDetector fast(c);
  int fast_onsets = 0;
  for (int i = 0; i < 60; ++i) fast_onsets += fast.update(from_yaw_pitch_deg(150.0 * i / 120.0, 0.0), i * kPeriodNs).onset;
  EXPECT_EQ(fast_onsets, 1) << "150 deg/s is above the 75 deg/s threshold";
}

TEST(SaccadeDetector, ThresholdIsConfigurable) {
  SaccadeConfig c;
  c.onset_velocity_deg_s = 30.0;
  c.offset_velocity_deg_s = 20.0;
  SaccadeDetector d(c);
  int onsets = 0;
  for (int i = 0; i < 60; ++i) onsets += d.update(from_yaw_pitch_deg(40.0 * i / 120.0, 0.0), i * kPeriodNs).onset;
  EXPECT_EQ(onsets, 1) << "40 deg/s exceeds a 30 deg/s threshold";
}

TEST(GazeHold, HoldsThenReportsLost) {
  FilterConfig c;
  c.one_euro.enabled = false;
  FilterChain chain(c);
  for (int i = 0; i < 10; ++i) chain.process(sample_at_yaw(5.0, i));
  int held = 0, lost = 0;
  for (int i = 10; i < 70; ++i) {  // 500 ms without valid gaze
    const GazeSample out = chain.process(sample_at_yaw(0.0, i, false));
    const double since_ms = (i - 9) * kPeriodNs * 1e-6;
    if (since_ms <= 200.0) {
      EXPECT_TRUE(out.valid && out.held && !out.lost) << "sample " << i;
      EXPECT_NEAR(to_yaw_pitch_deg(out.combined_direction).yaw_deg, 5.0, 1e-4) << "reuses the last valid gaze";
      ++held;
    } else {
      EXPECT_TRUE(!out.valid && out.lost) << "sample " << i;
      ++lost;
    }
  }
  EXPECT_EQ(held, 24);
  EXPECT_EQ(lost, 36);
  const GazeSample back = chain.process(sample_at_yaw(1.0, 70));
  EXPECT_TRUE(back.valid && !back.held && !back.lost);
}

TEST(GazeHold, DisabledHoldReportsLostImmediately) {
  FilterConfig c;
  c.hold.enabled = false;
  FilterChain chain(c);
  chain.process(sample_at_yaw(5.0, 0));
  const GazeSample out = chain.process(sample_at_yaw(0.0, 1, false));
  EXPECT_FALSE(out.valid);
  EXPECT_TRUE(out.lost);
}

TEST(FilterChain, NanDirectionIsInvalid) {
  FilterChain chain;
  GazeSample s = sample_at_yaw(0.0, 0);
  s.combined_direction.x = std::nanf("");
  const GazeSample out = chain.process(s);
  EXPECT_FALSE(out.valid);
  EXPECT_TRUE(out.lost);
}
