// gaze-diag end to end: stream -> record -> report (JSON keys, plots), and bad traces.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

struct Result {
  int exit_code = -1;
  std::string out;
};

Result run(const std::string& args) {
  Result r;
  const std::string cmd = std::string(GAZE_DIAG_EXE) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string temp_dir() {
  const auto d = std::filesystem::temp_directory_path() / ("foveart_diag_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d.string();
}

}  // namespace

TEST(GazeDiag, StreamRecordReport) {
  const std::string dir = temp_dir();
  const Result stream = run("stream --source sim:3 --seconds 1 --json --record " + dir + "/t.csv");
  ASSERT_EQ(stream.exit_code, 0) << stream.out;
  for (const char* key : {"\"samples\"", "\"duration_s\"", "\"rate_hz\"", "\"interval_p50_ms\"", "\"interval_p99_ms\"",
                          "\"dropped\"", "\"valid_fraction\"", "\"saccades\"", "\"blinks\"", "\"latency_p50_ms\""})
    EXPECT_NE(stream.out.find(key), std::string::npos) << key << " in " << stream.out;

  const Result report = run("report " + dir + "/t.csv --json --png " + dir + "/plot");
  ASSERT_EQ(report.exit_code, 0) << report.out;
  EXPECT_NE(report.out.find("\"rate_hz\": 120.0000"), std::string::npos) << report.out;
  EXPECT_GT(std::filesystem::file_size(dir + "/plot_heatmap.png"), 1000u);
  EXPECT_GT(std::filesystem::file_size(dir + "/plot_timeseries.png"), 1000u);
  std::filesystem::remove_all(dir);
}

TEST(GazeDiag, ReportAccuracyWithTargets) {
  const std::string dir = temp_dir();
  {
    std::ofstream out(dir + "/cal.csv");
    out << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z,target_x,target_y,target_z\n"
           "0,0,1,0,0,1,0,0,1\n8333,1,1,0.0174524,0,0.9998477,0,0,1\n";
  }
  const Result r = run("report " + dir + "/cal.csv --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\"accuracy_deg\": 0.5000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"precision_deg\": 1.0000"), std::string::npos) << r.out;
  std::filesystem::remove_all(dir);
}

TEST(GazeDiag, BadInputsExitNonZeroWithLineNumbers) {
  const std::string dir = temp_dir();
  {
    std::ofstream out(dir + "/bad.csv");
    out << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n0,0,1,0,0,1\n8333,1,1,0,0\n";
  }
  { std::ofstream empty(dir + "/empty.csv"); }
  Result r = run("report " + dir + "/bad.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(dir + "/bad.csv:3: truncated row"), std::string::npos) << r.out;
  r = run("report " + dir + "/empty.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("empty"), std::string::npos) << r.out;
  r = run("stream --source nonsense --seconds 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("unknown gaze source"), std::string::npos) << r.out;
  r = run("stream --source sim --seconds 1 --hid-layout size=2");
  EXPECT_EQ(r.exit_code, 1);
  r = run("list --json --fove-library /nonexistent/libFoveClient.so");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\"loadable\": false"), std::string::npos) << r.out;
  std::filesystem::remove_all(dir);
}
