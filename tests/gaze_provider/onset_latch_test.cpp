// Saccades and blinks that begin and end between two looks at the gaze are still
// seen by the next look (OnsetLatch), through the onset times the chain carries.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "gaze_provider/filters.h"
#include "gaze_provider/gaze_math.h"
#include "gaze_provider/onset_latch.h"

#include "tracker_period.hpp"

using namespace foveart::gaze;

namespace {

// 10 deg minimum-jerk saccade from `from_deg`, starting at sample `start`, 43 ms long.
double saccade_yaw_deg(double from_deg, int start, int i) {
  const double t = (i - start) * kPeriodNs * 1e-9 / 0.043;
  const double tau = std::clamp(t, 0.0, 1.0);
  return from_deg + 10.0 * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
}

GazeSample raw_sample(int i, double yaw_deg, bool valid) {
  GazeSample s;
  s.device_time_ns = (i + 1) * kPeriodNs;
  s.host_time_ns = s.device_time_ns;
  s.frame_id = static_cast<std::uint64_t>(i);
  s.valid = valid;
  s.eye_state = valid ? EyeState::open : EyeState::closed;
  s.combined_direction = from_yaw_pitch_deg(yaw_deg, 0.0);
  return s;
}

// Fixation, a saccade at sample 30, a 3-sample blink at 70, a second saccade at 102.
std::vector<GazeSample> filtered_script(int samples) {
  FilterChain chain;
  std::vector<GazeSample> out;
  for (int i = 0; i < samples; ++i) {
    const double yaw_deg = i < 102 ? saccade_yaw_deg(0.0, 30, i) : saccade_yaw_deg(10.0, 102, i);
    const bool blinking = i >= 70 && i < 73;
    out.push_back(chain.process(raw_sample(i, yaw_deg, !blinking)));
  }
  return out;
}
}  // namespace

TEST(GazeHold, EverySampleOfOneHoldCarriesItsFirstSamplesTime) {
  const auto samples = filtered_script(90);
  EXPECT_EQ(samples[69].hold_onset_device_ns, 0) << "no hold before the blink";
  for (int i = 70; i < 73; ++i) {
    ASSERT_TRUE(samples[i].held) << "sample " << i;
    EXPECT_EQ(samples[i].hold_onset_device_ns, samples[70].device_time_ns) << "sample " << i;
  }
  EXPECT_FALSE(samples[73].held);
  EXPECT_EQ(samples[89].hold_onset_device_ns, samples[70].device_time_ns) << "the last hold, until the next";
}

TEST(OnsetLatch, LooksTooSlowToSeeTheStateStillSeeEverySaccadeAndBlinkOnce) {
  const auto samples = filtered_script(140);
  // Every 12th sample: a 10 Hz consumer (a slow frame loop) whose looks all miss the
  // flags themselves; the saccades (~5 flagged samples) and the blink fall between.
  OnsetLatch latch;
  std::vector<int> saccade_looks, hold_looks;
  for (int i = 5; i < 140; i += 12) {
    const GazeSample& newest = samples[i];
    ASSERT_FALSE(newest.in_saccade || newest.held) << "the premise: look " << i << " misses the flags";
    const OnsetLatch::Began began = latch.update(newest);
    if (began.saccade) saccade_looks.push_back(i);
    if (began.hold) hold_looks.push_back(i);
  }
  EXPECT_EQ(saccade_looks, (std::vector<int>{41, 113})) << "the first look after each saccade, once";
  EXPECT_EQ(hold_looks, (std::vector<int>{77})) << "the first look after the blink, once";
}

TEST(OnsetLatch, WhatBeganBeforeTheFirstLookIsNotNews) {
  const auto samples = filtered_script(90);
  ASSERT_NE(samples[89].saccade_onset_device_ns, 0);
  ASSERT_NE(samples[89].hold_onset_device_ns, 0);
  OnsetLatch latch;
  const OnsetLatch::Began first = latch.update(samples[89]);
  EXPECT_FALSE(first.saccade || first.hold);
  const OnsetLatch::Began again = latch.update(samples[89]);
  EXPECT_FALSE(again.saccade || again.hold) << "the same sample twice";
}

TEST(OnsetLatch, AChainRestartedAfterADisconnectIsNoEvent) {
  const auto samples = filtered_script(90);
  OnsetLatch latch;
  latch.update(samples[89]);
  GazeSample restarted = samples[89];  // a chain reset clears its onset times
  restarted.saccade_onset_device_ns = 0;
  restarted.hold_onset_device_ns = 0;
  const OnsetLatch::Began began = latch.update(restarted);
  EXPECT_FALSE(began.saccade || began.hold);
}
