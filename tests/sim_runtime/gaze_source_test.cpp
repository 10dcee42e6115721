// The runtime's gaze source: the gaze-diag CSV reader and the built-in script.
#include "gaze_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "xr_test_app.h"

namespace foveart::sim {
namespace {

std::string write_file(const std::string& dir, const std::string& text) {
  const std::string path = dir + "/trace.csv";
  std::ofstream(path) << text;
  return path;
}

TEST(GazeSource, ReadsTraceAndHoldsEachSampleUntilTheNext) {
  const std::string dir = test::fresh_dir("trace");
  const std::string path =
      write_file(dir,
                 "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z,pupil_mm\n"
                 "# comment\n"
                 "5000,1,1,0,0,-1,3.1\n"
                 "13333,2,1,0,0.6,-0.8,3.2\n"
                 "21667,3,0,0,0,0,0\n");
  std::string error;
  auto source = GazeSource::from_csv_file(path, error);
  ASSERT_TRUE(source) << error;
  EXPECT_EQ(source->trace_size(), 3U);
  GazeSample s = source->sample_at(8'000'000);  // 8 ms after the first row: still row 1
  EXPECT_EQ(s.offset_ns, 0);
  EXPECT_TRUE(s.valid);
  EXPECT_FLOAT_EQ(s.direction.z, -1.0F);
  s = source->sample_at(8'333'000);  // exactly row 2
  EXPECT_EQ(s.offset_ns, 8'333'000);
  EXPECT_NEAR(s.direction.y, 0.6F, 1e-6F);
  s = source->sample_at(16'700'000);  // row 3 is a blink
  EXPECT_FALSE(s.valid);
}

TEST(GazeSource, TraceLoopsAfterItsLastSample) {
  const std::string dir = test::fresh_dir("trace");
  const std::string path = write_file(
      dir, "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,1,0,0,-1\n10000,2,1,1,0,0\n");
  std::string error;
  auto source = GazeSource::from_csv_file(path, error);
  ASSERT_TRUE(source) << error;
  // Period = last time (10 ms) + one 120 Hz sample (8.333 ms).
  const GazeSample s = source->sample_at(18'333'333 + 1'000'000);
  EXPECT_EQ(s.offset_ns, 18'333'333);
  EXPECT_FLOAT_EQ(s.direction.z, -1.0F);
}

TEST(GazeSource, MalformedTracesAreRejectedWithFileAndLine) {
  const std::string dir = test::fresh_dir("trace");
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"time,frame,valid,x,y,z\n0,1,1,0,0,-1\n", "trace.csv:1: header"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,1,0,zero,-1\n",
       "trace.csv:2: column gaze_y"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,2,0,0,-1\n",
       "trace.csv:2: column valid"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,1,0,0,0\n", "zero gaze direction"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n10,1,1,0,0,-1\n5,2,1,0,0,-1\n",
       "goes backwards"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n", "no samples"},
      {"", "no header"},
  };
  for (const Case& c : cases) {
    std::string error;
    EXPECT_FALSE(GazeSource::from_csv_file(write_file(dir, c.text), error)) << c.text;
    EXPECT_NE(error.find(c.expect), std::string::npos) << error;
  }
  std::string error;
  EXPECT_FALSE(GazeSource::from_csv_file(dir + "/missing.csv", error));
  EXPECT_NE(error.find("cannot open"), std::string::npos);
}

TEST(GazeSource, BuiltInScriptIsUnitGazeAt120HzWithSaccadesAndABlink) {
  const GazeSource script = GazeSource::saccade_script();
  int invalid = 0;
  float max_step_deg = 0.0F;
  glm::vec3 previous{0.0F, 0.0F, -1.0F};
  for (int64_t t = 0; t < 2'400'000'000; t += 8'333'333) {
    const GazeSample s = script.sample_at(t);
    EXPECT_EQ(s.offset_ns % 8'333'333, 0);
    EXPECT_NEAR(glm::length(s.direction), 1.0F, 1e-5F);
    if (!s.valid) {
      ++invalid;
      continue;
    }
    const float step =
        glm::degrees(std::acos(std::clamp(glm::dot(previous, s.direction), -1.0F, 1.0F)));
    max_step_deg = std::max(max_step_deg, step);
    previous = s.direction;
  }
  EXPECT_GE(invalid, 20);         // ~200 ms blink per 2.4 s cycle
  EXPECT_GT(max_step_deg, 2.0F);  // saccades move several degrees per sample
}

}  // namespace
}  // namespace foveart::sim
