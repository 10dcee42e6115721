// Host transfers and waits counted at the Vulkan boundary by a Vulkan layer of
// our own (VK_LAYER_FOVEART_count, count_layer.cpp), not inside the functions
// under test: every submission, fence / idle / semaphore / query wait, map and
// flush a process makes, with its caller, per device.
//
// Positive controls (VkCountProbe): vk_count_probe renders frames the pipelined
// way (one submission and one wait on the frame before last per frame); adding
// a full-image read-back or a wait on this frame's fence per frame shows up as
// exactly that per frame, and the budget helper that holds the GPU path to its
// numbers fails on them, once per frame and exceeded limit (its failures caught
// with gtest-spi's reporter), while the plain probe meets even the pipelined
// acceptance.
//
// The GPU path (VkCountGpuPath): hello_foveated --engine gpu, "reconstruction":
// "gpu", through the real OpenXR loader, the layer, the simulated runtime and
// lavapipe, under the counting layer. Frames are split at the app's own
// submissions (its placeholder clear, one per eye per frame); the layer's calls
// (and the GPU engine's, called back by it) per frame are printed and every
// steady frame is held to the pipelined acceptance, so a read-back or a wait
// on this frame added to the frame path fails.
#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "child_process.hpp"
#include "test_env.hpp"
#include "vk_counts.hpp"

namespace foveart::vk_count {
namespace {

namespace fs = std::filesystem;
using foveart::layer::test::IsolatedEnv;
using foveart::test::ProcessResult;
using foveart::test::run_process;

constexpr int kTimeoutS = 600;

// The counting layer on for children started after this; the counts into <root>/<name>.jsonl.
fs::path count_into(const IsolatedEnv& env, const std::string& name) {
  const fs::path out = env.root() / (name + ".jsonl");
  fs::remove(out);
  IsolatedEnv::set("VK_LAYER_PATH", FOVEART_VK_COUNT_LAYER_DIR);
  IsolatedEnv::set("VK_INSTANCE_LAYERS", "VK_LAYER_FOVEART_count");
  IsolatedEnv::set("FOVEART_VK_COUNT_OUT", out);
  return out;
}

void stop_counting() {
  for (const char* name : {"VK_LAYER_PATH", "VK_INSTANCE_LAYERS", "FOVEART_VK_COUNT_OUT"}) ::unsetenv(name);
}

// The one device record of a run (the probe and hello_foveated each make one device).
nlohmann::json one_record(const fs::path& file, const ProcessResult& run) {
  const auto records = read_records(file);
  EXPECT_EQ(records.size(), 1u) << "device records in " << file << "; the run said:\n" << run.output;
  if (records.size() != 1 || records[0].is_discarded()) return nullptr;
  return records[0];
}

// hello_foveated's --json object: from the line that opens it to the line that closes
// it (the layer logs before it; a sanitizer may report after it); null without one.
nlohmann::json app_json(const std::string& output) {
  const auto open = output.find("\n{");
  const auto close = open == std::string::npos ? open : output.find("\n}", open);
  if (close == std::string::npos) return nullptr;
  return nlohmann::json::parse(output.substr(open + 1, close + 1 - open), nullptr, false);
}

// ---- the positive controls ----------------------------------------------------------------

constexpr int kProbeFrames = 6;
constexpr uint64_t kProbeW = 320, kProbeH = 360, kProbeImageBytes = kProbeW * kProbeH * 4;

class VkCountProbe : public ::testing::Test {
 protected:
  void SetUp() override { env_ = std::make_unique<IsolatedEnv>(); }
  void TearDown() override { stop_counting(); }

  // The probe's steady frames (the first two, before any slot is reused, left out)
  // under the counting layer, with `extra` arguments.
  std::vector<Frame> run(const std::string& name, const std::vector<std::string>& extra) {
    const fs::path out = count_into(*env_, name);
    std::vector<std::string> args{FOVEART_VK_COUNT_PROBE, "--frames", std::to_string(kProbeFrames), "--size",
                                  std::to_string(kProbeW), std::to_string(kProbeH)};
    args.insert(args.end(), extra.begin(), extra.end());
    const ProcessResult r = run_process(args, env_->root() / (name + ".log"), kTimeoutS);
    stop_counting();
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json record = one_record(out, r);
    if (record.is_null()) return {};
    const Roles roles{"vk_count_probe"};
    auto frames = split_frames(
        record, roles, [](const nlohmann::json& e, const std::string& who) {
          return who == "app" && e["call"] == "vkQueueSubmit";
        },
        1);
    print_frames(("vk_count_probe " + name).c_str(), frames);
    // Frames 0 .. kProbeFrames - 2 are complete; frame 0 has no slot to wait for yet.
    EXPECT_EQ(frames.size(), std::size_t{kProbeFrames - 1});
    if (!frames.empty()) frames.erase(frames.begin());
    return frames;
  }

  std::unique_ptr<IsolatedEnv> env_;
};

// What the probe does without extras: one submission, one wait on an older frame.
Tally probe_baseline() {
  Tally t;
  t.submissions = 1;
  t.command_buffers = 1;
  t.waits_older_frame = 1;
  return t;
}

// The pipelined acceptance of the GPU path, also met by the plain probe: no host
// wait on this frame's work, at most one submission per frame, no read-back (no
// map, no invalidation, no copy into mapped memory).
HostBudget pipelined_acceptance() {
  HostBudget b;
  b.submissions = 1;
  b.waits_this_frame = 0;
  b.maps = 0;
  b.invalidates = 0;
  b.copies_to_host = 0;
  return b;
}

// A budget that is exactly `t` (nothing may grow).
HostBudget exactly(const Tally& t) {
  HostBudget b;
  b.submissions = t.submissions;
  b.waits_this_frame = t.waits_this_frame;
  b.waits_older_frame = t.waits_older_frame;
  b.waits_unsubmitted = t.waits_unsubmitted;
  b.fence_polls = t.fence_polls;
  b.query_reads = t.query_reads;
  b.maps = t.maps;
  b.mapped_bytes = t.mapped_bytes;
  b.invalidates = t.invalidates;
  b.invalidated_bytes = t.invalidated_bytes;
  b.flushes = t.flushes;
  b.flushed_bytes = t.flushed_bytes;
  b.copies_to_host = t.copies_to_host;
  b.copies_from_host = t.copies_from_host;
  return b;
}

void expect_all_within(const std::vector<Frame>& frames, const char* who, const HostBudget& budget) {
  for (std::size_t i = 0; i < frames.size(); ++i) expect_within(sum(frames[i], {who}), budget, who, int(i));
}

// What expect_all_within(frames, "app", budget) reports, kept from the test's result:
// how many failures for each exceeded limit ("vkMapMemory calls": 4).
std::map<std::string, int> budget_failures(const std::vector<Frame>& frames, const HostBudget& budget) {
  ::testing::TestPartResultArray results;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    expect_all_within(frames, "app", budget);
  }
  std::map<std::string, int> failures;
  for (int i = 0; i < results.size(); ++i) {
    const std::string message = results.GetTestPartResult(i).message();
    const auto colon = message.rfind(": "), end = message.rfind(" per frame over the budget");
    failures[colon != std::string::npos && end != std::string::npos && end > colon
                 ? message.substr(colon + 2, end - colon - 2)
                 : message] += 1;
  }
  return failures;
}

TEST_F(VkCountProbe, ThePipelinedProbeIsOneSubmissionAndOneOlderWaitPerFrame) {
  const auto frames = run("baseline", {});
  ASSERT_FALSE(frames.empty());
  for (const Frame& f : frames) {
    EXPECT_EQ(f.size(), 1u) << "only the probe calls Vulkan";
    EXPECT_EQ(sum(f, {"app"}), probe_baseline());
  }
  expect_all_within(frames, "app", pipelined_acceptance());
}

// One full-image read-back per frame (map + invalidate of width x height x 4 bytes,
// and the unmap): exactly that on top of the baseline, and the budgets catch it.
TEST_F(VkCountProbe, AReadBackPerFrameIsCountedExactlyAndBreaksTheBudget) {
  const auto frames = run("readback", {"--readback"});
  ASSERT_FALSE(frames.empty());
  Tally expected = probe_baseline();
  expected.maps = 1;
  expected.mapped_bytes = kProbeImageBytes;
  expected.invalidates = 1;
  expected.invalidated_bytes = kProbeImageBytes;
  expected.unmaps = 1;
  for (const Frame& f : frames) EXPECT_EQ(sum(f, {"app"}), expected);
  // Held to the baseline, every frame fails on exactly the read-back's four counts;
  // held to the pipelined acceptance, on its map and invalidation.
  const int n = static_cast<int>(frames.size());
  const std::map<std::string, int> against_baseline{{"vkMapMemory calls", n},
                                                    {"vkMapMemory bytes", n},
                                                    {"vkInvalidateMappedMemoryRanges calls", n},
                                                    {"vkInvalidateMappedMemoryRanges bytes", n}};
  EXPECT_EQ(budget_failures(frames, exactly(probe_baseline())), against_baseline);
  const std::map<std::string, int> against_acceptance{{"vkMapMemory calls", n},
                                                      {"vkInvalidateMappedMemoryRanges calls", n}};
  EXPECT_EQ(budget_failures(frames, pipelined_acceptance()), against_acceptance);
}

// One full-image read-back per frame through a staging buffer mapped once at
// start-up (no map or invalidation per frame): the copy into it is counted.
TEST_F(VkCountProbe, AReadBackThroughAPersistentMapIsCountedAsACopyToTheHost) {
  const auto frames = run("staging", {"--staging"});
  ASSERT_FALSE(frames.empty());
  Tally expected = probe_baseline();
  expected.copies_to_host = 1;
  expected.to_host_bytes = kProbeImageBytes;
  for (const Frame& f : frames) EXPECT_EQ(sum(f, {"app"}), expected);
  const std::map<std::string, int> expected_failures{
      {"copies into mapped memory (read-backs)", int(frames.size())}};
  EXPECT_EQ(budget_failures(frames, exactly(probe_baseline())), expected_failures);
  EXPECT_EQ(budget_failures(frames, pipelined_acceptance()), expected_failures);
}

// One wait on this frame's fence per frame: exactly that on top of the baseline,
// and the budgets catch it.
TEST_F(VkCountProbe, AWaitOnThisFramePerFrameIsCountedExactlyAndBreaksTheBudget) {
  const auto frames = run("wait", {"--wait"});
  ASSERT_FALSE(frames.empty());
  Tally expected = probe_baseline();
  expected.waits_this_frame = 1;
  for (const Frame& f : frames) EXPECT_EQ(sum(f, {"app"}), expected);
  // Every frame fails on exactly that, held to the baseline or to the pipelined acceptance.
  const std::map<std::string, int> expected_failures{{"host waits on this frame's work", int(frames.size())}};
  EXPECT_EQ(budget_failures(frames, exactly(probe_baseline())), expected_failures);
  EXPECT_EQ(budget_failures(frames, pipelined_acceptance()), expected_failures);
}

// ---- the GPU path ---------------------------------------------------------------------------

constexpr int kAppFrames = 8;
// Frames before the steady state: the runtime lays out each swapchain image on its
// first acquire, and the layer creates its eyes in frame 0.
constexpr int kWarmUpFrames = 3;

class VkCountGpuPath : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(foveart::layer::test::have_runtime()) << "the simulated runtime's manifest is missing";
    env_ = std::make_unique<IsolatedEnv>();
    foveart::layer::test::configure_hello_foveated(*env_, kAppFrames, "gpu");
    IsolatedEnv::set("FOVEART_SIM_HEAD", "static");
    ::unsetenv("FOVEART_SIM_CAPTURE_DIR");  // no capture: the runtime's read-back is not the layer's
  }
  void TearDown() override { stop_counting(); }

  // hello_foveated --engine gpu under the counting layer: its complete frames.
  std::vector<Frame> run() {
    const fs::path out = count_into(*env_, "gpu_path");
    const ProcessResult r = run_process(
        {FOVEART_HELLO_FOVEATED, "--json", "--engine", "gpu", "--eye-size", "320", "360", "--interpolation", "msm",
         "--k", "5", "--density-scale", "4", "--rays-per-point", "1", "--temporal", "off"},
        env_->root() / "gpu_path.log", kTimeoutS);
    stop_counting();
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json stats = app_json(r.output);
    EXPECT_TRUE(stats.is_object() && stats["views_fallback"] == 0 && stats["reconstruction"] == "gpu")
        << "every view on the GPU path, reconstructed there:\n" << r.output;
    const nlohmann::json record = one_record(out, r);
    if (record.is_null()) return {};
    const Roles roles{fs::path(FOVEART_HELLO_FOVEATED).filename().string()};
    older_wait_ages_ = older_wait_ages(record, roles);
    // The app's placeholder clear, one submission per eye: two per frame.
    auto frames = split_frames(
        record, roles, [](const nlohmann::json& e, const std::string& who) {
          return who == "app" && e["call"] == "vkQueueSubmit";
        },
        2);
    print_frames("hello_foveated --engine gpu, reconstruction gpu: host calls per frame at the Vulkan boundary",
                 frames);
    // The GPU engine is compiled into the app, so its scene upload through staging (before
    // the first frame) counts as the app's submissions too: at most one more split.
    EXPECT_GE(frames.size(), std::size_t{kAppFrames - 1}) << "complete frames between the app's clears";
    EXPECT_LE(frames.size(), std::size_t{kAppFrames}) << "complete frames between the app's clears";
    return frames;
  }

  // Holds the layer's (and engine's) calls of every steady frame to `budget`.
  void expect_steady_frames_within(const std::vector<Frame>& frames, const HostBudget& budget) {
    ASSERT_GT(frames.size(), std::size_t{kWarmUpFrames + 1});
    for (std::size_t i = kWarmUpFrames; i < frames.size(); ++i)
      expect_within(sum(frames[i], {"layer", "engine"}), budget, "layer + engine", int(i));
  }

  // For each of the layer's (and engine's) waits on an older frame, in order:
  // how many of their own submissions are newer than the one it waits for, plus
  // one (1: the frame before, 2: the one before that, ...).
  static std::vector<uint64_t> older_wait_ages(const nlohmann::json& record, const Roles& roles) {
    std::vector<uint64_t> submitted, ages;
    for (const auto& e : record["events"]) {
      const std::string role = role_of(e, roles);
      if (role != "layer" && role != "engine") continue;
      const uint64_t submission = e.value("submission", uint64_t{0});
      if (e["call"] == "vkQueueSubmit" || e["call"] == "vkQueueSubmit2") submitted.push_back(submission);
      if (e["call"] != "vkWaitForFences" || e["kind"] != "older_frame") continue;
      const auto it = std::find(submitted.begin(), submitted.end(), submission);
      ages.push_back(it == submitted.end() ? 0 : uint64_t(submitted.end() - it));
    }
    return ages;
  }

  std::unique_ptr<IsolatedEnv> env_;
  std::vector<uint64_t> older_wait_ages_;  // run()'s, older_wait_ages
};

// The pipelined frame (docs/gpu.md): both eyes recorded into one command buffer
// and submitted once, no host wait on this frame's work, nothing read back
// through a map, an invalidation or a copy; the layer waits only on an older
// frame (its slot's previous submission), at most once a frame, and does wait:
// it reuses its slots, and each such wait is on frame n - 2 or older: at
// least two frames are in flight (the counting layer records which submission
// a wait's fences signal).
TEST_F(VkCountGpuPath, EverySteadyFrameMeetsThePipelinedAcceptance) {
  const auto frames = run();
  ASSERT_GT(frames.size(), std::size_t{kWarmUpFrames + 1});
  uint64_t older_waits = 0;
  for (std::size_t i = kWarmUpFrames; i < frames.size(); ++i) {
    const Tally t = sum(frames[i], {"layer", "engine"});
    EXPECT_EQ(t.submissions, 1u) << "frame " << i << ": both eyes in one submission";
    EXPECT_EQ(t.command_buffers, 1u) << "frame " << i << ": both eyes in one command buffer";
    EXPECT_LE(t.waits_older_frame, 1u) << "frame " << i << ": one wait for the slot's previous submission";
    older_waits += t.waits_older_frame;
    // The app's own: its two placeholder clears, each waited for.
    EXPECT_EQ(sum(frames[i], {"app"}).submissions, 2u) << "frame " << i;
  }
  EXPECT_GT(older_waits, 0u) << "the layer reuses its frame slots after their submissions finished";
  ASSERT_GE(older_wait_ages_.size(), older_waits);
  for (std::size_t i = older_wait_ages_.size() - older_waits; i < older_wait_ages_.size(); ++i)
    EXPECT_GE(older_wait_ages_[i], 2u) << "steady wait " << i << " is on the frame just before: one frame in flight";
  expect_steady_frames_within(frames, pipelined_acceptance());
}

// With content density on the device trace the frame is the same at the Vulkan boundary: the
// eyes' tiles persist on the device (frame n reads frame n-1's in queue order), so nothing is
// read back or waited for, and both eyes stay one submission.
TEST_F(VkCountGpuPath, ContentDensityKeepsThePipelinedAcceptance) {
  foveart::layer::test::configure_hello_foveated(*env_, kAppFrames, "gpu", {},
                                                 R"("content_contrast": 0.1, "content_rays": 0.2)");
  const auto frames = run();
  ASSERT_GT(frames.size(), std::size_t{kWarmUpFrames + 1});
  for (std::size_t i = kWarmUpFrames; i < frames.size(); ++i) {
    const Tally t = sum(frames[i], {"layer", "engine"});
    EXPECT_EQ(t.submissions, 1u) << "frame " << i << ": both eyes in one submission";
    EXPECT_EQ(t.command_buffers, 1u) << "frame " << i << ": both eyes in one command buffer";
  }
  expect_steady_frames_within(frames, pipelined_acceptance());
}

}  // namespace
}  // namespace foveart::vk_count
