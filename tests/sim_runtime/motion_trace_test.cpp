// A scripted motion's gaze exported as a gaze trace (sim-motion-trace): the provider's
// reader gets the runtime's samples row for row, the runtime replays it as the motion's
// own gaze, and the provider's filter chain finds the script's saccade and blink in it.
#include "motion_trace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <vector>

#include "gaze_provider/filters.h"
#include "gaze_provider/trace_csv.h"
#include "gaze_source.h"
#include "sim_test_env.h"
#include "motion_math.hpp"

namespace foveart::sim {
namespace {

using test::ns;
using test::angle_deg;

std::string builtin_trace(const MotionSource& motion, double seconds) {
  const std::string path = test::fresh_dir("trace") + "/motion_gaze.csv";
  std::string error;
  EXPECT_TRUE(write_motion_gaze_trace_file(motion, seconds, path, &error)) << error;
  return path;
}

TEST(MotionTrace, ProvidersReaderGetsTheRuntimesSamplesRowForRow) {
  const MotionSource motion(motion::builtin_motion(1), "builtin");
  const std::string path = builtin_trace(motion, 4.0);
  gaze::TraceError error;
  const auto trace = gaze::read_trace_file(path, &error);
  ASSERT_TRUE(trace.has_value()) << error.to_string();
  ASSERT_EQ(trace->rows.size(), 481u) << "0 to 4 s at 120 Hz";
  EXPECT_EQ(trace->skipped_non_monotonic, 0u);
  int invalid = 0;
  int64_t t = 0;
  for (const gaze::TraceRow& row : trace->rows) {
    const GazeSample expected = motion.gaze_at(t);
    ASSERT_EQ(row.sample.device_time_ns, expected.offset_ns);
    ASSERT_EQ(row.sample.valid, expected.valid) << "at " << expected.offset_ns << " ns";
    if (expected.valid) {
      const gaze::Vec3f& d = row.sample.combined_direction;
      EXPECT_LT(angle_deg(glm::vec3(d.x, d.y, d.z), expected.direction), 1e-4) << expected.offset_ns;
    }
    invalid += expected.valid ? 0 : 1;
    t = motion.next_sample_ns(t);
  }
  EXPECT_EQ(invalid, 18) << "the 150 ms blink at 120 Hz";
}

TEST(MotionTrace, RuntimeReplayingTheTraceShowsTheMotionsGaze) {
  // FOVEART_SIM_GAZE=trace and FOVEART_SIM_MOTION=builtin give the same eye tracker
  // within the first loop (the trace then loops a sample period later than the motion).
  const MotionSource motion(motion::builtin_motion(1), "builtin");
  std::string error;
  const auto replay = GazeSource::from_trace_file(builtin_trace(motion, 4.0), &error);
  ASSERT_TRUE(replay.has_value()) << error;
  for (int64_t t = 0; t < ns(4.0); t += 5'000'000) {
    const GazeSample a = replay->sample_at(t);
    const GazeSample b = motion.gaze_at(t);
    ASSERT_EQ(a.offset_ns, b.offset_ns) << t;
    ASSERT_EQ(a.valid, b.valid) << t;
    if (a.valid) {
      ASSERT_LT(angle_deg(a.direction, b.direction), 1e-4) << t;
    }
  }
}

TEST(MotionTrace, LongerTracesLoopTheMotionAndStayMonotonic) {
  const MotionSource motion(motion::builtin_motion(1), "builtin");
  gaze::TraceError error;
  const auto trace = gaze::read_trace_file(builtin_trace(motion, 12.0), &error);
  ASSERT_TRUE(trace.has_value()) << error.to_string();
  EXPECT_EQ(trace->skipped_non_monotonic, 0u);
  EXPECT_EQ(trace->rows.size(), 3u * 480u + 1u);
  // Row 480 starts the second loop: the script's first sample again, at 4 s.
  EXPECT_EQ(trace->rows[480].sample.device_time_ns, ns(4.0));
  const gaze::Vec3f& a = trace->rows[0].sample.combined_direction;
  const gaze::Vec3f& b = trace->rows[480].sample.combined_direction;
  EXPECT_LT(angle_deg(glm::vec3(a.x, a.y, a.z), glm::vec3(b.x, b.y, b.z)), 1e-4);
}

// The provider's own signal chain on the exported trace, sample by sample (no
// clock involved): its I-VT detector flags the scripted 12 deg saccade and nothing
// else (microsaccades, drift and tracker noise stay below 75 deg/s), and its hold
// bridges exactly the blink.
TEST(MotionTrace, ProvidersFilterChainFlagsTheScriptedSaccadeAndHoldsTheBlink) {
  const MotionSource motion(motion::builtin_motion(1), "builtin");
  gaze::TraceError error;
  // One loop: rows 0-479 (the loop's restart at 4 s is a gaze jump, a saccade too).
  const auto trace = gaze::read_trace_file(builtin_trace(motion, 3.995), &error);
  ASSERT_TRUE(trace.has_value()) << error.to_string();
  ASSERT_EQ(trace->rows.size(), 480u);
  gaze::FilterChain chain;
  std::vector<double> saccade_s, held_s;
  for (const gaze::TraceRow& row : trace->rows) {
    const gaze::GazeSample out = chain.process(row.sample);
    const double t_s = static_cast<double>(row.sample.device_time_ns) * 1e-9;
    if (out.in_saccade) saccade_s.push_back(t_s);
    if (out.held) held_s.push_back(t_s);
    EXPECT_FALSE(out.lost) << t_s;
  }
  ASSERT_FALSE(saccade_s.empty());
  EXPECT_GE(saccade_s.front(), 1.5);
  EXPECT_LT(saccade_s.back(), 1.6);
  ASSERT_EQ(held_s.size(), 18u);
  EXPECT_GE(held_s.front(), 3.0);
  EXPECT_LT(held_s.back(), 3.15);
}

}  // namespace
}  // namespace foveart::sim
