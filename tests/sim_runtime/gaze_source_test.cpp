// The runtime's gaze source: traces through the gaze provider's one reader (head
// space, +z forward), what gaze-diag records, and the built-in script.
#include "gaze_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <sstream>

#include "gaze_provider/gaze_math.h"
#include "gaze_provider/trace_csv.h"
#include "xr_test_app.h"

namespace foveart::sim {
namespace {

std::string write_file(const std::string& dir, const std::string& text) {
  const std::string path = dir + "/trace.csv";
  std::ofstream(path) << text;
  return path;
}

glm::vec3 to_glm(const gaze::Vec3f& v) { return {v.x, v.y, v.z}; }

// A gaze sample as a recorder sees it: 120 Hz, both eyes along the combined gaze.
gaze::GazeSample recorded(int64_t device_time_ns, uint64_t frame, bool valid, gaze::Vec3f direction) {
  gaze::GazeSample s;
  s.device_time_ns = device_time_ns;
  s.host_time_ns = device_time_ns + 2'000'000;
  s.frame_id = frame;
  s.valid = valid;
  s.eye_state = valid ? gaze::EyeState::open : gaze::EyeState::closed;
  s.confidence = valid ? 0.95F : 0.0F;
  s.combined_direction = direction;
  s.left = {{-0.032F, 0.0F, 0.0F}, direction, valid, s.eye_state};
  s.right = {{0.032F, 0.0F, 0.0F}, direction, valid, s.eye_state};
  return s;
}

TEST(GazeSource, ReadsTheTraceInHeadSpaceAndHoldsEachSampleUntilTheNext) {
  const std::string dir = test::fresh_dir("trace");
  const std::string path = write_file(dir,
                                      "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z,pupil_mm\n"
                                      "5000,1,1,0,0,1,3.1\n"
                                      "13333,2,1,0,0.6,0.8,3.2\n"
                                      "21667,3,0,0,0,0,0\n");
  std::string error;
  auto source = GazeSource::from_trace_file(path, &error);
  ASSERT_TRUE(source) << error;
  EXPECT_EQ(source->trace_size(), 3U);
  GazeSample s = source->sample_at(8'000'000);  // 8 ms after the first row: still row 1
  EXPECT_EQ(s.offset_ns, 0);
  EXPECT_TRUE(s.valid);
  EXPECT_FLOAT_EQ(s.direction.z, 1.0F) << "+z is forward in a trace";
  s = source->sample_at(8'333'000);  // exactly row 2
  EXPECT_EQ(s.offset_ns, 8'333'000);
  EXPECT_NEAR(s.direction.y, 0.6F, 1e-6F);
  EXPECT_NEAR(s.direction.z, 0.8F, 1e-6F);
  s = source->sample_at(16'700'000);  // row 3 is a blink
  EXPECT_FALSE(s.valid);
}

// Issue 14: the runtime reads the dialect of gaze-diag, because it is the same
// reader: a BOM, NaN in an invalid row, and device times on a
// Unix-epoch microsecond clock (1.7e15 us, once refused above 9e12 us).
TEST(GazeSource, ReadsUnixEpochTimesBomAndNanRowsAsGazeDiagDoes) {
  const std::string dir = test::fresh_dir("trace");
  const std::string text =
      "\xEF\xBB\xBF" "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n"
      "1700000000000000,1,1,0,0,1\n"
      "1700000000008333,2,0,nan,nan,nan\n"
      "1700000000016667,3,1,0,0.6,0.8\n";
  const std::string path = write_file(dir, text);
  std::string error;
  auto source = GazeSource::from_trace_file(path, &error);
  ASSERT_TRUE(source) << error;
  gaze::TraceError diag_error;
  std::istringstream in(text);
  const auto diag = gaze::read_trace(in, &diag_error);
  ASSERT_TRUE(diag) << diag_error.to_string();
  ASSERT_EQ(source->trace_size(), diag->rows.size());
  EXPECT_EQ(source->trace_size(), 3U);
  EXPECT_TRUE(source->sample_at(0).valid);
  EXPECT_FALSE(source->sample_at(8'333'000).valid) << "the NaN row is a blink";
  const GazeSample s = source->sample_at(16'667'000);
  EXPECT_EQ(s.offset_ns, 16'667'000) << "offsets from the first row, whatever the epoch";
  EXPECT_NEAR(s.direction.y, 0.6F, 1e-6F);
}

TEST(GazeSource, OpenXrViewDirectionKeepsRightAndUpAndTurnsForwardToMinusZ) {
  const glm::vec3 v = openxr_view_direction(glm::vec3(0.25F, 0.17F, 0.95F));
  EXPECT_FLOAT_EQ(v.x, 0.25F);
  EXPECT_FLOAT_EQ(v.y, 0.17F);
  EXPECT_FLOAT_EQ(v.z, -0.95F);
}

TEST(GazeSource, TraceLoopsAfterItsLastSample) {
  const std::string dir = test::fresh_dir("trace");
  const std::string path =
      write_file(dir, "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,1,0,0,1\n10000,2,1,1,0,0\n");
  std::string error;
  auto source = GazeSource::from_trace_file(path, &error);
  ASSERT_TRUE(source) << error;
  // Period = last time (10 ms) + one 120 Hz sample (8.333 ms).
  const GazeSample s = source->sample_at(18'333'333 + 1'000'000);
  EXPECT_EQ(s.offset_ns, 18'333'333);
  EXPECT_FLOAT_EQ(s.direction.z, 1.0F);
}

// What the provider's writer produces (and so gaze-diag --record): every optional
// column, a blink whose directions are nan, and a repeated frame. The runtime's
// former reader of its own refused the nan row.
TEST(GazeSource, ReadsWhatTheProvidersWriterWritesBlinksAndRepeatsIncluded) {
  const std::string dir = test::fresh_dir("trace");
  const std::string path = dir + "/trace.csv";
  const gaze::Vec3f left_up = gaze::from_yaw_pitch_deg(-15.0, 10.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  {
    std::ofstream out(path);
    gaze::TraceWriter writer(out);
    writer.write(recorded(1'000'000'000, 0, true, left_up));
    writer.write(recorded(1'008'333'333, 1, false, {nan, nan, nan}));
    writer.write(recorded(1'008'333'333, 1, false, {nan, nan, nan}));  // repeated frame
    writer.write(recorded(1'016'666'667, 2, true, left_up));
    ASSERT_TRUE(writer.ok());
  }
  std::string error;
  auto source = GazeSource::from_trace_file(path, &error);
  ASSERT_TRUE(source) << error;
  EXPECT_EQ(source->trace_size(), 3U);
  EXPECT_EQ(source->skipped_rows(), 1U);
  const GazeSample first = source->sample_at(0);
  ASSERT_TRUE(first.valid);
  EXPECT_NEAR(glm::distance(first.direction, to_glm(left_up)), 0.0F, 1e-6F);
  EXPECT_FALSE(source->sample_at(8'333'333).valid);
  const GazeSample third = source->sample_at(16'666'667);
  EXPECT_EQ(third.offset_ns, 16'666'667) << "nanoseconds survive the microsecond column";
  EXPECT_TRUE(third.valid);
}

TEST(GazeSource, MalformedTracesAreRejectedWithFileAndLine) {
  const std::string dir = test::fresh_dir("trace");
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"time,frame,valid,x,y,z\n0,1,1,0,0,1\n", "trace.csv:1: "},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,1,0,zero,1\n", "trace.csv:2: "},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,2,0,0,1\n", "'valid'"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,1,1,0,0,0\n", "zero gaze direction"},
      {"device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n", "no samples"},
      {"", "empty file"},
  };
  for (const Case& c : cases) {
    std::string error;
    EXPECT_FALSE(GazeSource::from_trace_file(write_file(dir, c.text), &error)) << c.text;
    EXPECT_NE(error.find(c.expect), std::string::npos) << error;
    EXPECT_NE(error.find("trace.csv"), std::string::npos) << error;
  }
  std::string error;
  EXPECT_FALSE(GazeSource::from_trace_file(dir + "/missing.csv", &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos);
}

// gaze-diag's recording of a replayed trace (its real output, every column it
// writes) reads back through the runtime with the directions and times it played.
TEST(GazeSource, ReadsAGazeDiagRecording) {
  const std::string dir = test::fresh_dir("diag");
  const gaze::Vec3f left_up = gaze::from_yaw_pitch_deg(-15.0, 10.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  {
    std::ofstream out(dir + "/played.csv");
    gaze::TraceWriter writer(out);
    for (int i = 0; i < 24; ++i) {
      const bool blink = i >= 10 && i < 14;
      writer.write(recorded(5'000'000'000 + i * 8'333'333LL, static_cast<uint64_t>(i), !blink,
                            blink ? gaze::Vec3f{nan, nan, nan} : left_up));
    }
  }
  const std::string command = std::string(FOVEART_GAZE_DIAG) + " stream --source replay:" + dir +
                              "/played.csv --fast --seconds 20 --json --record " + dir + "/recorded.csv > " + dir +
                              "/diag.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::string error;
  auto source = GazeSource::from_trace_file(dir + "/recorded.csv", &error);
  ASSERT_TRUE(source) << error;
  ASSERT_EQ(source->trace_size(), 24U);
  EXPECT_EQ(source->skipped_rows(), 0U);
  for (int i = 0; i < 24; ++i) {
    const GazeSample s = source->sample_at(i * 8'333'333LL);
    EXPECT_EQ(s.offset_ns, i * 8'333'333LL) << i;
    EXPECT_EQ(s.valid, i < 10 || i >= 14) << i;
    if (s.valid) {
      EXPECT_NEAR(glm::distance(s.direction, to_glm(left_up)), 0.0F, 1e-6F) << i;
    }
  }
}

TEST(GazeSource, BuiltInScriptIsUnitForwardGazeAt120HzWithSaccadesAndABlink) {
  const GazeSource script = GazeSource::saccade_script();
  int invalid = 0;
  float max_step_deg = 0.0F;
  glm::vec3 previous{0.0F, 0.0F, 1.0F};
  for (int64_t t = 0; t < 2'400'000'000; t += 8'333'333) {
    const GazeSample s = script.sample_at(t);
    EXPECT_EQ(s.offset_ns % 8'333'333, 0);
    EXPECT_NEAR(glm::length(s.direction), 1.0F, 1e-5F);
    if (!s.valid) {
      ++invalid;
      continue;
    }
    EXPECT_GT(s.direction.z, 0.9F) << "head space: the script looks forward, along +z";
    const float step = glm::degrees(std::acos(std::clamp(glm::dot(previous, s.direction), -1.0F, 1.0F)));
    max_step_deg = std::max(max_step_deg, step);
    previous = s.direction;
  }
  EXPECT_GE(invalid, 20);         // ~200 ms blink per 2.4 s cycle
  EXPECT_GT(max_step_deg, 2.0F);  // saccades move several degrees per sample
  // The second fixation, (12, 6) deg: right and up.
  const GazeSample second = script.sample_at(440'000'000 + 100'000'000);
  EXPECT_NEAR(glm::degrees(std::atan2(second.direction.x, second.direction.z)), 12.0F, 1e-3F);
  EXPECT_GT(second.direction.y, 0.0F);
}

}  // namespace
}  // namespace foveart::sim
