// HID backend: report layout parsing/decoding, and a full stream through hidapi from a
// synthetic hidraw device replayed by umockdev (umockdev-run, no root needed).
//
// HidUmockdev.* tests re-run this executable under umockdev-run, where the inner test
// HidUmockdev.DISABLED_InsideTestbed (disabled in normal runs) does the streaming.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gaze_provider/backends.h"

extern char** environ;

using namespace foveart::gaze;
using namespace std::chrono_literals;

namespace {

constexpr int kReports = 60;

struct Expected {
  std::uint32_t time_us;      // as sent: a 32-bit microsecond clock that wraps at k = 21
  std::uint64_t unwrapped_us;  // as the backend must report it
  std::uint32_t frame;
  bool valid;
  EyeState state;
  std::uint8_t conf;
  Vec3f dir;
};

Expected expected_report(int k) {
  Expected e;
  e.unwrapped_us = 4'294'800'000ull + std::uint64_t(k) * 8333u;
  e.time_us = std::uint32_t(e.unwrapped_us & 0xffffffffu);
  e.frame = std::uint32_t(500 + k + (k >= 40 ? 2 : 0));   // two frames dropped before k = 40
  const bool blink = k >= 20 && k < 25;
  e.valid = !blink;
  e.state = blink ? EyeState::closed : EyeState::open;
  e.conf = std::uint8_t(blink ? 0 : 200 + (k % 50));
  e.dir = from_yaw_pitch_deg(-10.0 + 0.3 * k, 2.0 - 0.05 * k);
  return e;
}

std::vector<std::uint8_t> encode(const Expected& e) {
  std::vector<std::uint8_t> r(24, 0);
  r[0] = 0x01;  // report id: never 0x20 as a block's first byte (umockdev 0.17.16 drops it)
  std::memcpy(&r[1], &e.time_us, 4);
  std::memcpy(&r[5], &e.frame, 4);
  r[9] = std::uint8_t((e.valid ? 1 : 0) | (int(e.state) << 1));
  r[10] = e.conf;
  std::memcpy(&r[12], &e.dir.x, 4);
  std::memcpy(&r[16], &e.dir.y, 4);
  std::memcpy(&r[20], &e.dir.z, 4);
  return r;
}

// umockdev script: "r <delay ms> <data>"; bytes < 32 escaped as '^' + (b + 64), '^' as "^`".
// (script-format.txt says "<= 32", but its reader turns "^`" into '^', so a space must
// stay verbatim; and a block's leading space is eaten as a separator: report ids != 0x20.)
void write_script(const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  for (int k = 0; k < kReports; ++k) {
    std::string line = "r " + std::to_string(k % 3 == 2 ? 9 : 8) + " ";
    for (std::uint8_t b : encode(expected_report(k))) {
      if (b == '^') line += "^`";
      else if (b < 32) line += {'^', char(b + 64)};
      else line += char(b);
    }
    out << line << '\n';
  }
}

std::string self_exe() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

struct TestbedRun {
  int exit_code = -1;
  std::string output;  // the child's stdout and stderr
};

TestbedRun run_in_testbed(const std::string& source) {
  const std::string dir = std::filesystem::temp_directory_path() / ("foveart_hid_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string script = dir + "/hidraw0.script";
  const std::string log = dir + "/child.log";
  write_script(script);
  const std::string data = GAZE_TEST_DATA_DIR;
  std::vector<std::string> args = {"umockdev-run",
                                   "-d", data + "/synthetic_eye_tracker.umockdev",
                                   "-i", "/dev/hidraw0=" + data + "/hidraw0.ioctl",
                                   "-s", "/dev/hidraw0=" + script,
                                   "--", self_exe(),
                                   "--gtest_also_run_disabled_tests",
                                   "--gtest_filter=HidUmockdev.DISABLED_InsideTestbed"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The preload library comes after the sanitizer runtime: tell ASan that is fine.
  std::string asan = std::getenv("ASAN_OPTIONS") ? std::getenv("ASAN_OPTIONS") : "";
  if (asan.find("verify_asan_link_order") == std::string::npos)
    setenv("ASAN_OPTIONS", (asan + (asan.empty() ? "" : ":") + "verify_asan_link_order=0").c_str(), 1);
  setenv("FOVEART_HID_TEST_SOURCE", source.c_str(), 1);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  TestbedRun run;
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "umockdev-run", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned == 0) {
    int status = 0;
    waitpid(pid, &status, 0);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::ifstream in(log);
    std::ostringstream text;
    text << in.rdbuf();
    run.output = text.str();
  }
  std::filesystem::remove_all(dir);
  return run;
}

// The child ran exactly the one inner test and it passed: its own summary line
// says so (a filter that matches nothing also exits 0, with "0 tests").
void expect_inner_test_passed(const TestbedRun& run) {
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("[  PASSED  ] 1 test.\n"), std::string::npos)
      << "the child did not run and pass exactly one test:\n" << run.output;
}

}  // namespace

TEST(HidLayout, DefaultSpecRoundTripsAndBadSpecsFail) {
  std::string error;
  auto l = HidReportLayout::parse(HidReportLayout{}.to_string(), &error);
  ASSERT_TRUE(l) << error;
  EXPECT_EQ(l->size, 24u);
  EXPECT_EQ(l->gaze_offset, 12u);
  l = HidReportLayout::parse("id=none,size=16,time=u64@0,frame=u32@8,flags=u8@12,conf=none,gaze=i16@12", &error);
  EXPECT_FALSE(l) << "gaze (6 bytes at 12) ends beyond size=16";
  EXPECT_NE(error.find("beyond"), std::string::npos) << error;
  l = HidReportLayout::parse("id=none,size=20,time=u64@0,frame=u32@8,flags=u8@12,conf=none,gaze=i16@13", &error);
  ASSERT_TRUE(l) << error;
  EXPECT_EQ(l->report_id, -1);
  EXPECT_FALSE(HidReportLayout::parse("size=24,bogus=1", &error));
  EXPECT_NE(error.find("bogus"), std::string::npos);
  EXPECT_FALSE(HidReportLayout::parse("gaze=f64@4", &error));
  EXPECT_FALSE(HidReportLayout::parse("size=8", &error)) << "default fields do not fit in 8 bytes";
}

TEST(HidLayout, OffsetsNearTwoToTheSixtyFourAreRejectedNotWrapped) {
  // Before the fix, offset + width wrapped to a small number, the layout passed, and decoding read 2^64 bytes away.
  std::string error;
  auto l = HidReportLayout::parse("size=24,gaze=f32@18446744073709551615", &error);
  EXPECT_FALSE(l) << "gaze offset 2^64-1 accepted";
  EXPECT_NE(error.find("gaze"), std::string::npos) << error;
  EXPECT_NE(error.find("18446744073709551615"), std::string::npos) << error;
  EXPECT_NE(error.find("beyond"), std::string::npos) << error;
  // 2^64 - 4 + 4 (u32 frame) wraps to exactly 0 <= size.
  error.clear();
  l = HidReportLayout::parse("size=24,frame=u32@18446744073709551612", &error);
  EXPECT_FALSE(l) << "frame offset + width wraps to 0";
  EXPECT_NE(error.find("frame"), std::string::npos) << error;
  // 2^64 - 1 + 1 (u8 conf) wraps to 0 as well, on the optional field.
  error.clear();
  l = HidReportLayout::parse("size=24,conf=u8@18446744073709551615", &error);
  EXPECT_FALSE(l) << "conf offset + width wraps to 0";
  EXPECT_NE(error.find("conf"), std::string::npos) << error;
  // A field that ends exactly at size still fits.
  EXPECT_TRUE(HidReportLayout::parse("size=24,gaze=f32@12", &error)) << error;
}

TEST(HidLayout, DecodesReports) {
  const Expected e = expected_report(3);
  const std::vector<std::uint8_t> r = encode(e);
  std::uint64_t t = 0, f = 0;
  GazeSample s;
  ASSERT_TRUE(decode_hid_report(HidReportLayout{}, r.data(), r.size(), t, f, s));
  EXPECT_EQ(t, e.time_us);
  EXPECT_EQ(f, e.frame);
  EXPECT_TRUE(s.valid);
  EXPECT_NEAR(s.confidence, e.conf / 255.0f, 1e-6);
  EXPECT_LT(angle_between_deg(s.combined_direction, e.dir), 1e-4);
  EXPECT_FALSE(decode_hid_report(HidReportLayout{}, r.data(), 10, t, f, s)) << "short report";
  std::vector<std::uint8_t> other = r;
  other[0] = 2;
  EXPECT_FALSE(decode_hid_report(HidReportLayout{}, other.data(), other.size(), t, f, s)) << "other report id";
}

TEST(HidUmockdev, StreamsByVidPid) { expect_inner_test_passed(run_in_testbed("hid:2a5e:0001")); }

TEST(HidUmockdev, FindsEyeTrackerUsagePage) { expect_inner_test_passed(run_in_testbed("hid")); }

TEST(HidUmockdev, StreamsByPath) {
  expect_inner_test_passed(run_in_testbed("hid:/dev/hidraw0"));
}

TEST(HidUmockdev, PathThatIsNotHidrawIsAnError) {
  // hidapi's hid_open_path crashed on a character device that is not hidraw: the path must be one it lists.
  for (const char* path : {"/dev/null", "/no/such/hidraw"}) {
    CreateResult created = create_gaze_provider(std::string("hid:") + path);
    EXPECT_FALSE(created) << path;
    EXPECT_NE(created.error.find(std::string(path) + ": not a HID device"), std::string::npos) << created.error;
  }
}

TEST(HidUmockdev, MissingDeviceIsAnError) {
  CreateResult created = create_gaze_provider("hid:dead:beef");
  EXPECT_FALSE(created);
  EXPECT_NE(created.error.find("dead:beef"), std::string::npos) << created.error;
  EXPECT_FALSE(create_gaze_provider("hid:xyz"));
}

TEST(HidUmockdev, DISABLED_InsideTestbed) {
  ASSERT_NE(std::getenv("UMOCKDEV_DIR"), nullptr) << "run through HidUmockdev.StreamsByVidPid";
  const char* source = std::getenv("FOVEART_HID_TEST_SOURCE");
  CreateResult created = create_gaze_provider(source ? source : "hid");
  ASSERT_TRUE(created) << created.error;
  GazeProvider& p = *created.provider;
  std::string error;
  ASSERT_TRUE(p.start(&error)) << error;
  std::vector<GazeSample> all, buf(64);
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (all.size() < std::size_t(kReports) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(5ms);
    const std::size_t n = p.read_raw(buf);
    all.insert(all.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
  }
  p.stop();
  ASSERT_EQ(all.size(), std::size_t(kReports));
  for (int k = 0; k < kReports; ++k) {
    const Expected e = expected_report(k);
    const GazeSample& s = all[std::size_t(k)];
    EXPECT_EQ(s.source, GazeSourceKind::hid);
    EXPECT_EQ(s.frame_id, e.frame) << k;
    EXPECT_EQ(s.device_time_ns, std::int64_t(e.unwrapped_us) * 1000) << k;
    EXPECT_EQ(s.valid, e.valid) << k;
    EXPECT_EQ(s.eye_state, e.state) << k;
    if (e.valid) {
      EXPECT_LT(angle_between_deg(s.combined_direction, e.dir), 1e-4) << k;
    }
  }
}
