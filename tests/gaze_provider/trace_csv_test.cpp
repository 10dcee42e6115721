// Trace CSV: round trip, optional/unknown columns, and every kind of bad trace.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "gaze_provider/simulator.h"
#include "gaze_provider/trace_csv.h"
#include "gaze_provider/trace_stats.h"

using namespace foveart::gaze;

namespace {
const char* kHeader = "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";

TraceError read_error(const std::string& text) {
  std::istringstream in(text);
  TraceError e;
  EXPECT_FALSE(read_trace(in, &e).has_value()) << "should have failed: " << text;
  return e;
}
}  // namespace

TEST(TraceCsv, RoundTripIsBitIdentical) {
  GazeSimulator sim;
  std::vector<GazeSample> original;
  std::ostringstream out;
  TraceWriter w(out);
  for (int i = 0; i < 500; ++i) {
    GazeSample s = sim.next();
    s.host_time_ns = s.device_time_ns + 123'457;  // sub-microsecond part must survive
    original.push_back(s);
    w.write(s);
  }
  std::istringstream in(out.str());
  TraceError e;
  auto trace = read_trace(in, &e);
  ASSERT_TRUE(trace) << e.to_string();
  ASSERT_EQ(trace->rows.size(), original.size());
  for (std::size_t i = 0; i < original.size(); ++i) {
    const GazeSample& a = original[i];
    const GazeSample& b = trace->rows[i].sample;
    ASSERT_EQ(a.device_time_ns, b.device_time_ns) << i;
    ASSERT_EQ(a.host_time_ns, b.host_time_ns) << i;
    ASSERT_EQ(a.frame_id, b.frame_id);
    ASSERT_EQ(a.valid, b.valid);
    ASSERT_EQ(a.eye_state, b.eye_state);
    ASSERT_EQ(a.confidence, b.confidence);
    ASSERT_EQ(a.combined_direction.x, b.combined_direction.x) << i;
    ASSERT_EQ(a.combined_direction.y, b.combined_direction.y);
    ASSERT_EQ(a.combined_direction.z, b.combined_direction.z);
    ASSERT_EQ(a.left.origin_m.x, b.left.origin_m.x);
    ASSERT_EQ(a.right.direction.y, b.right.direction.y);
    ASSERT_EQ(a.left.valid, b.left.valid);
  }
}

// Device clocks count from their own epoch: FOVE's microsecond timestamps, a Unix-epoch
// time, a monotonic clock after 105 days of uptime (9.07e15 ns, which the reader used to
// refuse as "not a decimal number of microseconds"). Whatever the writer writes reads
// back; only times whose nanoseconds overflow int64 are errors.
TEST(TraceCsv, FarEpochDeviceTimesRoundTrip) {
  const std::int64_t times_ns[] = {9'072'000'000'000'123, 1'700'000'000'000'000'456,
                                   std::numeric_limits<std::int64_t>::max()};
  std::ostringstream out;
  TraceWriter w(out);
  for (const std::int64_t t : times_ns) {
    GazeSample s;
    s.device_time_ns = t;
    s.host_time_ns = t;
    s.valid = true;
    s.eye_state = EyeState::open;
    s.confidence = 1.0f;
    w.write(s);
  }
  std::istringstream in(out.str());
  TraceError e;
  auto trace = read_trace(in, &e);
  ASSERT_TRUE(trace) << e.to_string();
  ASSERT_EQ(trace->rows.size(), std::size(times_ns));
  for (std::size_t i = 0; i < std::size(times_ns); ++i) {
    EXPECT_EQ(trace->rows[i].sample.device_time_ns, times_ns[i]) << i;
    EXPECT_EQ(trace->rows[i].sample.host_time_ns, times_ns[i]) << i;
  }
  EXPECT_EQ(read_error(std::string(kHeader) + "9223372036854775.808,0,1,0,0,1\n").line, 2u) << "int64 overflow";
  EXPECT_EQ(read_error(std::string(kHeader) + "9223372036854776,0,1,0,0,1\n").line, 2u) << "int64 overflow";
  EXPECT_EQ(read_error(std::string(kHeader) + "--5,0,1,0,0,1\n").line, 2u);
}

TEST(TraceCsv, MinimalTraceWithUnknownColumnsAndTargets) {
  std::istringstream in(
      "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z,vendor_thing,target_x,target_y,target_z\n"
      "0,0,1,0,0,1,abc,0,0,1\n"
      "8333.333,1,1,0.0174524,0,0.9998477,xyz,0,0,1\n"
      "16666.667,3,0,nan,nan,nan,,0,0,1\n");
  TraceError e;
  auto trace = read_trace(in, &e);
  ASSERT_TRUE(trace) << e.to_string();
  ASSERT_EQ(trace->rows.size(), 3u);
  EXPECT_EQ(trace->rows[1].sample.device_time_ns, 8'333'333);
  EXPECT_TRUE(trace->has_targets);
  EXPECT_FALSE(trace->rows[2].sample.valid);
  const TraceStats st = compute_stats(*trace);
  EXPECT_EQ(st.dropped, 1u) << "frame 2 missing";
  ASSERT_TRUE(st.accuracy_deg.has_value());
  EXPECT_NEAR(*st.accuracy_deg, 0.5, 1e-3) << "mean of 0 and 1 deg";
  ASSERT_TRUE(st.precision_deg.has_value());
  EXPECT_NEAR(*st.precision_deg, 1.0, 1e-3);
  EXPECT_NEAR(st.valid_fraction, 2.0 / 3.0, 1e-9);
}

TEST(TraceCsv, EmptyFile) {
  const TraceError e = read_error("");
  EXPECT_EQ(e.line, 1u);
  EXPECT_NE(e.message.find("empty"), std::string::npos);
}

TEST(TraceCsv, WrongHeader) {
  const TraceError e = read_error("time,frame,valid,x,y,z\n0,0,1,0,0,1\n");
  EXPECT_EQ(e.line, 1u);
  EXPECT_NE(e.message.find("device_time_us"), std::string::npos);
  EXPECT_EQ(read_error("frame_id,device_time_us,valid,gaze_x,gaze_y,gaze_z\n").line, 1u) << "order matters";
}

TEST(TraceCsv, TruncatedLine) {
  const TraceError e = read_error(std::string(kHeader) + "0,0,1,0,0,1\n8333,1,1,0,0\n");
  EXPECT_EQ(e.line, 3u);
  EXPECT_NE(e.message.find("truncated"), std::string::npos) << e.message;
}

TEST(TraceCsv, NonNumericField) {
  const TraceError e = read_error(std::string(kHeader) + "0,0,1,0,0,1\n8333,1,1,0,zero,1\n");
  EXPECT_EQ(e.line, 3u);
  EXPECT_NE(e.message.find("gaze_y"), std::string::npos) << e.message;
  EXPECT_EQ(read_error(std::string(kHeader) + "12ab,0,1,0,0,1\n").line, 2u);
  EXPECT_EQ(read_error(std::string(kHeader) + "0,0,yes,0,0,1\n").line, 2u);
}

TEST(TraceCsv, NanDirectionInValidRow) {
  const TraceError e = read_error(std::string(kHeader) + "0,0,1,0,0,1\n8333,1,1,nan,0,1\n");
  EXPECT_EQ(e.line, 3u);
  EXPECT_NE(e.message.find("non-finite"), std::string::npos) << e.message;
  EXPECT_EQ(read_error(std::string(kHeader) + "0,0,1,0,0,0\n").line, 2u) << "zero vector is not a direction";
}

TEST(TraceCsv, NonMonotonicAndDuplicatedTimestampsAreSkippedAndCounted) {
  std::istringstream in(std::string(kHeader) +
                        "0,0,1,0,0,1\n"
                        "8333,1,1,0,0,1\n"
                        "8333,1,1,0,0,1\n"    // duplicate (line 4)
                        "4000,2,1,0,0,1\n"    // backwards (line 5)
                        "16667,2,1,0,0,1\n");
  TraceError e;
  auto trace = read_trace(in, &e);
  ASSERT_TRUE(trace) << e.to_string();
  EXPECT_EQ(trace->rows.size(), 3u);
  EXPECT_EQ(trace->skipped_non_monotonic, 2u);
  EXPECT_EQ(trace->first_skipped_line, 4u);
}

TEST(TraceCsv, HeaderOnlyAndMissingFile) {
  std::istringstream in(kHeader);
  auto trace = read_trace(in, nullptr);
  ASSERT_TRUE(trace);
  EXPECT_TRUE(trace->rows.empty());
  TraceError e;
  EXPECT_FALSE(read_trace_file("/nonexistent/trace.csv", &e));
  EXPECT_EQ(e.line, 0u);
  EXPECT_NE(e.message.find("cannot open"), std::string::npos);
  EXPECT_EQ(e.to_string(), "/nonexistent/trace.csv: cannot open for reading");
}

TEST(TraceCsv, ADirectoryOrAnEndlessLineIsNotATrace) {
  TraceError e;
  const std::string dir = std::filesystem::temp_directory_path().string();
  EXPECT_FALSE(read_trace_file(dir, &e));
  EXPECT_EQ(e.to_string(), dir + ": a directory, not a file");
  // A file of one endless line (/dev/zero, a binary file) stops at the line limit instead of reading on.
  e = read_error(std::string(100000, '\0'));
  EXPECT_EQ(e.line, 1u);
  EXPECT_NE(e.message.find("longer than 4096 bytes"), std::string::npos) << e.message;
  e = read_error(std::string(kHeader) + "0,0,1,0,0,1\n" + std::string(5000, '1') + "\n");
  EXPECT_EQ(e.line, 3u) << e.message;
  EXPECT_NE(e.message.find("not a gaze trace"), std::string::npos) << e.message;
}

TEST(TraceCsv, AFileErrorNamesFileAndLineAsCompilersDo) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "foveart_trace_csv_bad_row.csv";
  {
    std::ofstream out(path);
    out << kHeader << "1,1,1,0,0\n";
  }
  TraceError e;
  EXPECT_FALSE(read_trace_file(path.string(), &e));
  std::filesystem::remove(path);
  EXPECT_EQ(e.line, 2u);
  EXPECT_EQ(e.to_string().rfind(path.string() + ":2: truncated row", 0), 0u) << e.to_string();
  std::istringstream in(std::string(kHeader) + "1,1,1,0,0\n");
  EXPECT_FALSE(read_trace(in, &e));
  EXPECT_EQ(e.to_string().rfind("line 2: truncated row", 0), 0u) << "a stream has no file name: " << e.to_string();
}

TEST(TraceCsv, GarbageNeverCrashes) {
  // Random bytes after a valid header: every outcome is an error or a trace, never a crash.
  std::mt19937 rng(1);
  for (int round = 0; round < 200; ++round) {
    std::string text = kHeader;
    const int len = int(rng() % 200);
    for (int i = 0; i < len; ++i) text += "0123456789.,-\nnaie\r\x01"[rng() % 20];
    std::istringstream in(text);
    TraceError e;
    auto trace = read_trace(in, &e);
    if (!trace) {
      EXPECT_GE(e.line, 2u);
    }
  }
}
