// Simulated eye: determinism, main sequence, and saccade detection against its ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "gaze_provider/filters.h"
#include "gaze_provider/simulator.h"

using namespace foveart::gaze;

TEST(Simulator, SameSeedSameSamplesOtherSeedOtherSamples) {
  SimConfig c;
  c.seed = 42;
  GazeSimulator a(c), b(c);
  c.seed = 43;
  GazeSimulator other(c);
  int differ = 0;
  for (int i = 0; i < 2400; ++i) {
    const GazeSample x = a.next(), y = b.next(), z = other.next();
    ASSERT_EQ(std::memcmp(&x.combined_direction, &y.combined_direction, sizeof(Vec3f)), 0) << "sample " << i;
    ASSERT_EQ(x.valid, y.valid);
    ASSERT_EQ(x.device_time_ns, y.device_time_ns);
    differ += std::memcmp(&x.combined_direction, &z.combined_direction, sizeof(Vec3f)) != 0;
  }
  EXPECT_GT(differ, 2000);
}

TEST(Simulator, DeviceClockIs120Hz) {
  GazeSimulator sim;
  const GazeSample first = sim.next();
  GazeSample last = first;
  for (int i = 1; i <= 1200; ++i) last = sim.next();
  EXPECT_EQ(last.frame_id, 1200u);
  EXPECT_NEAR(double(last.device_time_ns - first.device_time_ns), 10e9, 1.0);
}

TEST(Simulator, MainSequence) {
  // Carpenter 1988 durations; peak velocity grows with amplitude and saturates.
  EXPECT_NEAR(GazeSimulator::saccade_duration_s(10.0), 0.043, 1e-9);
  EXPECT_NEAR(GazeSimulator::saccade_peak_velocity_deg_s(10.0), 1.875 * 10.0 / 0.043, 1e-6);
  EXPECT_LT(GazeSimulator::saccade_peak_velocity_deg_s(5.0), GazeSimulator::saccade_peak_velocity_deg_s(15.0));
  EXPECT_LT(GazeSimulator::saccade_peak_velocity_deg_s(40.0), 900.0);

  // Measured from the generated true direction: duration and peak speed per saccade.
  SimConfig c;
  c.noise_white_deg = c.noise_drift_deg = 0.0;
  c.blinks = c.microsaccades = false;
  GazeSimulator sim(c);
  int saccades = 0;
  Vec3f prev{};
  double peak = 0.0, amplitude = 0.0;
  int frames_in = 0;
  bool was_in = false;
  for (int i = 0; i < 120 * 30; ++i) {
    SimTruth t;
    sim.next(&t);
    if (t.in_saccade) {
      if (!was_in) {
        peak = 0.0;
        frames_in = 0;
      }
      peak = std::max(peak, angle_between_deg(t.true_direction, prev) * c.rate_hz);
      amplitude = t.amplitude_deg;
      ++frames_in;
    } else if (was_in) {
      ++saccades;
      const double expected_peak = GazeSimulator::saccade_peak_velocity_deg_s(amplitude);
      // 120 Hz undersamples short saccades: compare peaks only where >= 4 samples cover it.
      if (amplitude >= 6.0) {
        EXPECT_NEAR(peak, expected_peak, 0.15 * expected_peak) << "amplitude " << amplitude;
      } else {
        EXPECT_LE(peak, expected_peak * 1.01) << "amplitude " << amplitude;
      }
      EXPECT_NEAR(frames_in / c.rate_hz, GazeSimulator::saccade_duration_s(amplitude), 1.5 / c.rate_hz);
    }
    was_in = t.in_saccade;
    prev = t.true_direction;
  }
  EXPECT_GT(saccades, 40) << "fixations of 180-450 ms over 30 s";
}

TEST(Simulator, NoiseBlinksAndMicrosaccadesArePresent) {
  GazeSimulator sim;  // defaults: ~1 deg total noise, blinks, microsaccades
  double err2 = 0;
  int valid = 0, invalid_runs = 0, micro = 0;
  bool prev_valid = true, prev_in = false;
  for (int i = 0; i < 120 * 60; ++i) {
    SimTruth t;
    const GazeSample s = sim.next(&t);
    if (s.valid) {
      const double e = angle_between_deg(s.combined_direction, t.true_direction);
      err2 += e * e;
      ++valid;
    } else {
      EXPECT_EQ(s.eye_state, EyeState::closed);
      if (prev_valid) ++invalid_runs;
    }
    if (t.in_saccade && !prev_in && t.amplitude_deg < 1.0) ++micro;
    prev_valid = s.valid;
    prev_in = t.in_saccade;
  }
  const double rms = std::sqrt(err2 / valid);
  EXPECT_GT(rms, 0.6);
  EXPECT_LT(rms, 1.6) << "~1 deg of noise";
  EXPECT_GE(invalid_runs, 8) << "one blink every ~4 s over 60 s";
  EXPECT_LE(invalid_runs, 30);
  EXPECT_GE(micro, 20) << "microsaccades at ~1.2 Hz during fixations";
}

TEST(SaccadeDetection, MatchesSimulatedGroundTruth) {
  SimConfig c;
  c.seed = 11;
  c.microsaccades = false;  // ground truth counts saccades >= 2 deg
  c.blinks = false;
  GazeSimulator sim(c);
  FilterChain chain;  // default filters: I-VT at 75 deg/s
  std::vector<std::int64_t> truth_onsets, detected_onsets;
  std::int64_t last = 0;
  for (int i = 0; i < 120 * 60; ++i) {
    SimTruth t;
    const GazeSample s = sim.next(&t);
    if (t.saccade_onset) truth_onsets.push_back(s.device_time_ns);
    const GazeSample f = chain.process(s);
    if (f.saccade_onset_device_ns != last) {
      detected_onsets.push_back(f.saccade_onset_device_ns);
      last = f.saccade_onset_device_ns;
    }
  }
  // Match each true onset to a detection within 0..40 ms after it.
  std::size_t matched = 0, j = 0;
  for (std::int64_t t : truth_onsets) {
    while (j < detected_onsets.size() && detected_onsets[j] < t) ++j;
    if (j < detected_onsets.size() && detected_onsets[j] - t <= 40'000'000) {
      ++matched;
      ++j;
    }
  }
  ASSERT_GT(truth_onsets.size(), 100u);
  const double recall = double(matched) / double(truth_onsets.size());
  const double precision = double(matched) / double(detected_onsets.size());
  std::printf("[ measured ] I-VT vs ground truth: %zu true saccades, recall %.3f, precision %.3f\n",
              truth_onsets.size(), recall, precision);
  EXPECT_GE(recall, 0.97) << matched << " of " << truth_onsets.size();
  EXPECT_GE(precision, 0.97) << detected_onsets.size() << " detections";
}
