// Frames pipelined across threads, as game engines run them: one thread calls xrWaitFrame,
// another xrBeginFrame/xrEndFrame. OpenXR 1.0, xrWaitFrame: "A subsequent xrWaitFrame call
// must block until the previous frame has been begun with xrBeginFrame and must unblock
// independently of the corresponding call to xrEndFrame." On both clocks; under TSan too.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "xr_test_app.h"

namespace foveart::sim::test {
namespace {

// The frames the wait thread hands the render thread, in order.
class FrameQueue {
 public:
  void push(const XrFrameState& frame) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      frames_.push_back(frame);
    }
    ready_.notify_one();
  }
  XrFrameState pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return !frames_.empty(); });
    const XrFrameState frame = frames_.front();
    frames_.pop_front();
    return frame;
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<XrFrameState> frames_;
};

struct PipelineResult {
  int frames_ended = 0;
  int begin_errors = 0;  // xrBeginFrame not XR_SUCCESS (call order, or a discarded frame)
  int end_errors = 0;
  int wait_errors = 0;
  int display_time_steps_off_grid = 0;
  int display_times_not_increasing = 0;
};

// A wait thread and a render thread for `frames` frames. Every `slow_every`th frame the
// render thread works `slow_work` before xrBeginFrame, longer than a frame period, so a
// runtime that let the next xrWaitFrame return early would run ahead of it.
PipelineResult run_pipelined(XrTestApp& app, int frames, int slow_every, std::chrono::milliseconds slow_work) {
  const XrSession session = app.session;
  PipelineResult result;
  FrameQueue queue;
  std::thread wait_thread([&] {
    for (int i = 0; i < frames; ++i) {
      auto frame = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
      auto wait = xr<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
      if (xrWaitFrame(session, &wait, &frame) != XR_SUCCESS) {
        ++result.wait_errors;  // only this thread writes it until join
        frame.predictedDisplayTime = 0;
      }
      queue.push(frame);
      if (frame.predictedDisplayTime == 0) return;
    }
  });
  XrTime last_display = 0;
  for (int i = 0; i < frames; ++i) {
    const XrFrameState frame = queue.pop();
    if (frame.predictedDisplayTime == 0) break;
    if (slow_every > 0 && i % slow_every == slow_every - 1) std::this_thread::sleep_for(slow_work);
    auto begin = xr<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
    if (xrBeginFrame(session, &begin) != XR_SUCCESS) {
      ++result.begin_errors;
      break;
    }
    auto end = xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
    end.displayTime = frame.predictedDisplayTime;
    end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    if (xrEndFrame(session, &end) != XR_SUCCESS) {
      ++result.end_errors;
      break;
    }
    ++result.frames_ended;
    if (last_display != 0) {
      if (frame.predictedDisplayTime <= last_display) ++result.display_times_not_increasing;
      if ((frame.predictedDisplayTime - last_display) % frame.predictedDisplayPeriod != 0)
        ++result.display_time_steps_off_grid;
    }
    last_display = frame.predictedDisplayTime;
  }
  if (result.frames_ended != frames) {
    // A failed run: a wait may block on a frame nobody begins. Destroying the session releases it.
    xrDestroySession(app.session);
    app.session = XR_NULL_HANDLE;
  }
  wait_thread.join();
  return result;
}

void expect_every_frame_ran(const PipelineResult& r, int frames) {
  EXPECT_EQ(r.wait_errors, 0);
  EXPECT_EQ(r.begin_errors, 0) << "xrBeginFrame out of order: the wait thread ran ahead";
  EXPECT_EQ(r.end_errors, 0);
  EXPECT_EQ(r.frames_ended, frames);
  EXPECT_EQ(r.display_times_not_increasing, 0);
  EXPECT_EQ(r.display_time_steps_off_grid, 0);
}

class PipelinedFrames : public ::testing::Test {
 protected:
  void SetUp() override { clear_sim_env(); }
  // A session on `clock` ("real" or "virtual"), run to FOCUSED.
  void start(const char* clock) {
    set_env({{"FOVEART_SIM_CLOCK", clock}});
    ASSERT_EQ(app.create_instance(), XR_SUCCESS);
    ASSERT_EQ(app.create_session(), XR_SUCCESS);
    ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  }
  XrTestApp app;
};

TEST_F(PipelinedFrames, ThreeHundredFramesOnTheVirtualClock) {
  ASSERT_NO_FATAL_FAILURE(start("virtual"));
  expect_every_frame_ran(run_pipelined(app, 300, 10, std::chrono::milliseconds(2)), 300);
}

TEST_F(PipelinedFrames, ThreeHundredFramesOnTheRealClock) {
  ASSERT_NO_FATAL_FAILURE(start("real"));
  // Every 25th frame takes two and a half frame periods to render.
  expect_every_frame_ran(run_pipelined(app, 300, 25, std::chrono::milliseconds(36)), 300);
}

// The rule itself, on one frame: a second xrWaitFrame does not return before the first
// frame's xrBeginFrame, and returns after it without waiting for its xrEndFrame.
TEST_F(PipelinedFrames, SecondWaitBlocksUntilThePreviousFrameIsBegun) {
  ASSERT_NO_FATAL_FAILURE(start("virtual"));
  auto first = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  ASSERT_EQ(xrWaitFrame(app.session, nullptr, &first), XR_SUCCESS);

  std::atomic<bool> second_returned{false};
  XrResult second_result = XR_ERROR_RUNTIME_FAILURE;
  auto second = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  std::thread waiter([&] {
    second_result = xrWaitFrame(app.session, nullptr, &second);
    second_returned = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(second_returned.load()) << "the second xrWaitFrame returned before the first frame was begun";
  ASSERT_EQ(xrBeginFrame(app.session, nullptr), XR_SUCCESS);
  waiter.join();  // returns without the first frame's xrEndFrame
  EXPECT_EQ(second_result, XR_SUCCESS);
  EXPECT_EQ(second.predictedDisplayTime - first.predictedDisplayTime, first.predictedDisplayPeriod);

  auto end = xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  end.displayTime = first.predictedDisplayTime;
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_SUCCESS);
  EXPECT_EQ(xrBeginFrame(app.session, nullptr), XR_SUCCESS) << "the second frame begins";
  end.displayTime = second.predictedDisplayTime;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_SUCCESS);
}

}  // namespace
}  // namespace foveart::sim::test
