// Prediction to a target host time: bounded error on smooth pursuit, never across a
// saccade onset, interpolation inside the history, invalid when stale.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <deque>
#include <numbers>
#include <vector>

#include "gaze_provider/filters.h"

#include "tracker_period.hpp"

using namespace foveart::gaze;

namespace {
constexpr std::int64_t kLatencyNs = 5'000'000;  // host receives 5 ms after capture

double pursuit_yaw(double t_s) { return 10.0 * std::sin(2.0 * std::numbers::pi * 0.5 * t_s); }  // peak 31 deg/s

struct PursuitRun {
  double mean_error_predicted = 0, max_error_predicted = 0, mean_error_latest = 0;
};

PursuitRun run_pursuit(const FilterConfig& config, std::int64_t horizon_ns) {
  FilterChain chain(config);
  std::deque<GazeSample> history;  // newest first
  PursuitRun r;
  int n = 0;
  for (int i = 0; i < 600; ++i) {
    GazeSample s;
    s.device_time_ns = i * kPeriodNs;
    s.host_time_ns = s.device_time_ns + kLatencyNs;
    s.valid = true;
    s.eye_state = EyeState::open;
    s.combined_direction = from_yaw_pitch_deg(pursuit_yaw(double(s.device_time_ns) * 1e-9), 0.0);
    history.push_front(chain.process(s));
    if (history.size() > 16) history.pop_back();
    if (i < 120) continue;
    std::vector<GazeSample> w(history.begin(), history.end());
    const std::int64_t target = s.host_time_ns + horizon_ns;
    GazeSample out;
    EXPECT_TRUE(predict_gaze(w, target, config, out));
    const Vec3f truth = from_yaw_pitch_deg(pursuit_yaw(double(target - kLatencyNs) * 1e-9), 0.0);
    const double e = angle_between_deg(out.combined_direction, truth);
    r.mean_error_predicted += e;
    r.max_error_predicted = std::max(r.max_error_predicted, e);
    r.mean_error_latest += angle_between_deg(w[0].combined_direction, truth);
    ++n;
  }
  r.mean_error_predicted /= n;
  r.mean_error_latest /= n;
  return r;
}
}  // namespace

TEST(Prediction, SmoothPursuitErrorIsBounded) {
  FilterConfig raw;
  raw.one_euro.enabled = false;
  const PursuitRun r = run_pursuit(raw, 20'000'000);
  std::printf("[ measured ] pursuit 20 ms ahead, no smoothing: mean %.3f max %.3f deg (hold-last %.3f)\n",
              r.mean_error_predicted, r.max_error_predicted, r.mean_error_latest);
  EXPECT_LT(r.max_error_predicted, 0.25) << "20 ms ahead on a noise-free pursuit";
  EXPECT_LT(r.mean_error_predicted, 0.25 * r.mean_error_latest) << "prediction must beat holding the last sample";
}

TEST(Prediction, SmoothPursuitWithDefaultSmoothing) {
  const PursuitRun r = run_pursuit(FilterConfig{}, 20'000'000);
  std::printf("[ measured ] pursuit 20 ms ahead, default One Euro: mean %.3f max %.3f deg (hold-last %.3f)\n",
              r.mean_error_predicted, r.max_error_predicted, r.mean_error_latest);
  EXPECT_LT(r.mean_error_predicted, 0.6) << "One Euro lag + 20 ms horizon, default tuning";
  EXPECT_LT(r.mean_error_predicted, r.mean_error_latest);
}

TEST(Prediction, HorizonIsCapped) {
  FilterConfig raw;
  raw.one_euro.enabled = false;
  raw.prediction.max_horizon_ns = 10'000'000;
  FilterChain chain(raw);
  std::vector<GazeSample> w;
  for (int i = 0; i < 8; ++i) {
    GazeSample s;
    s.device_time_ns = s.host_time_ns = i * kPeriodNs;
    s.valid = true;
    s.combined_direction = from_yaw_pitch_deg(20.0 * i * kPeriodNs * 1e-9, 0.0);  // 20 deg/s
    w.insert(w.begin(), chain.process(s));
  }
  GazeSample out;
  ASSERT_TRUE(predict_gaze(w, w[0].host_time_ns + 100'000'000, raw, out));
  EXPECT_TRUE(out.extrapolated);
  const double moved = to_yaw_pitch_deg(out.combined_direction).yaw_deg - to_yaw_pitch_deg(w[0].combined_direction).yaw_deg;
  EXPECT_NEAR(moved, 20.0 * 0.010, 0.01) << "100 ms asked, 10 ms allowed";
}

TEST(Prediction, NeverExtrapolatesAcrossSaccadeOnset) {
  FilterConfig config;
  config.one_euro.enabled = false;
  FilterChain chain(config);
  std::vector<GazeSample> newest_first;
  int checked_in_saccade = 0, checked_after = 0;
  for (int i = 0; i < 120; ++i) {
    // slow drift (10 deg/s), then a 15 deg saccade at sample 60 (54 ms long)
    const double t = (i - 60) * kPeriodNs * 1e-9 / 0.054;
    const double tau = std::clamp(t, 0.0, 1.0);
    const double yaw = 10.0 * i / 120.0 + 15.0 * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
    GazeSample s;
    s.device_time_ns = s.host_time_ns = i * kPeriodNs;
    s.valid = true;
    s.combined_direction = from_yaw_pitch_deg(yaw, 0.0);
    newest_first.insert(newest_first.begin(), chain.process(s));
    if (newest_first.size() > 16) newest_first.pop_back();
    GazeSample out;
    ASSERT_TRUE(predict_gaze(newest_first, s.host_time_ns + 30'000'000, config, out));
    const GazeSample& newest = newest_first[0];
    if (newest.in_saccade) {
      EXPECT_FALSE(out.extrapolated) << "sample " << i;
      EXPECT_LT(angle_between_deg(out.combined_direction, newest.combined_direction), 1e-6);
      ++checked_in_saccade;
    } else if (i > 60 && newest.saccade_onset_device_ns > 0 && out.extrapolated) {
      // After landing: the fit window holds only post-onset samples, so the prediction
      // follows the slow drift, not the saccade's speed.
      const double jump = angle_between_deg(out.combined_direction, newest.combined_direction);
      EXPECT_LT(jump, 10.0 * 0.030 + 0.2) << "sample " << i;
      ++checked_after;
    }
  }
  EXPECT_GE(checked_in_saccade, 3);
  EXPECT_GE(checked_after, 20);
}

TEST(Prediction, InterpolatesInsideHistoryAndInvalidatesWhenStale) {
  FilterConfig config;
  std::vector<GazeSample> w(2);
  w[1].host_time_ns = 1'000'000'000;
  w[1].valid = true;
  w[1].combined_direction = from_yaw_pitch_deg(0.0, 0.0);
  w[0].host_time_ns = 1'010'000'000;
  w[0].valid = true;
  w[0].combined_direction = from_yaw_pitch_deg(2.0, 0.0);
  GazeSample out;
  ASSERT_TRUE(predict_gaze(w, 1'005'000'000, config, out));
  EXPECT_NEAR(to_yaw_pitch_deg(out.combined_direction).yaw_deg, 1.0, 1e-3);
  EXPECT_FALSE(out.extrapolated);
  ASSERT_TRUE(predict_gaze(w, 1'010'000'000 + 400'000'000, config, out));
  EXPECT_FALSE(out.valid) << "no sample for 400 ms: stale, the layer must fall back";
  EXPECT_TRUE(out.lost);
  EXPECT_FALSE(predict_gaze({}, 0, config, out));
}

TEST(Prediction, EyesFollowTheCombinedGaze) {
  FilterConfig config;  // default One Euro: the eyes are smoothed and predicted with it
  FilterChain chain(config);
  std::vector<GazeSample> w;
  for (int i = 0; i < 60; ++i) {
    const double yaw = 20.0 * double(i) * double(kPeriodNs) * 1e-9;  // 20 deg/s
    GazeSample s;
    s.device_time_ns = s.host_time_ns = i * kPeriodNs;
    s.valid = true;
    s.combined_direction = from_yaw_pitch_deg(yaw, 0.0);
    s.left = {{-0.032f, 0.0f, 0.0f}, from_yaw_pitch_deg(yaw + 1.0, 0.0), true, EyeState::open};
    s.right = {{0.032f, 0.0f, 0.0f}, from_yaw_pitch_deg(yaw - 1.0, 0.0), true, EyeState::open};
    w.insert(w.begin(), chain.process(s));
    if (w.size() > 16) w.pop_back();
  }
  GazeSample out;
  ASSERT_TRUE(predict_gaze(w, w[0].host_time_ns + 20'000'000, config, out));
  ASSERT_TRUE(out.extrapolated);
  const double c = to_yaw_pitch_deg(out.combined_direction).yaw_deg;
  EXPECT_NEAR(to_yaw_pitch_deg(out.left.direction).yaw_deg - c, 1.0, 1e-3) << "vergence kept";
  EXPECT_NEAR(to_yaw_pitch_deg(out.right.direction).yaw_deg - c, -1.0, 1e-3);
  EXPECT_GT(c, to_yaw_pitch_deg(w[0].combined_direction).yaw_deg + 0.2) << "moved ahead with the pursuit";
}
