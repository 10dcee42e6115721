// A fake FOVE client library for the tests: the same C entry points the FOVE backend
// resolves (gaze_provider/src/fove_c_api.h), scripting a 120 Hz eye-tracking stream.
//
// Script, by eye frame k (one frame per fove_Headset_waitForProcessedEyeFrame call;
// frame id = 1000 + k, timestamp = 5 s + k / 120 s in microseconds):
//   [  0,  30) eyes open, valid gaze, slow horizontal drift (yaw = 0.1 deg * k)
//   [ 30,  36) blink: both eyes Closed, gaze Data_Unreliable
//   [ 36,  60) valid
//   [ 60,  66) Data_LowAccuracy (valid direction, low confidence)
//   [ 66,  96) dropout: eyes NotDetected, gaze Data_Unreliable (250 ms > hold time)
//   [ 96, 100) valid
//   [100, 115) service lost: wait/fetch return Connect_NotConnected (no frames)
//   [115, ...) reconnected, valid
// Test controls (not part of the FOVE API): fake_fove_configure().
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <thread>

#include "fove_c_api.h"

struct Fove_Headset_ {
  int magic = 0x464f5645;
};

namespace {
std::atomic<std::uint64_t> g_period_us{8333};
std::atomic<int> g_fail_create{0};
std::atomic<int> g_stay_disconnected{0};
std::atomic<std::int64_t> g_frame{-1};  // current eye frame (advanced by wait)
std::atomic<std::int64_t> g_fetched{-1};

constexpr double kPi = 3.14159265358979323846;

bool disconnected(std::int64_t k) { return k >= 100 && (k < 115 || g_stay_disconnected.load() != 0); }
bool blink(std::int64_t k) { return k >= 30 && k < 36; }
bool low_accuracy(std::int64_t k) { return k >= 60 && k < 66; }
bool dropout(std::int64_t k) { return k >= 66 && k < 96; }

Fove_Vec3 direction(std::int64_t k) {
  const double yaw = 0.1 * double(k) * kPi / 180.0;
  return {float(std::sin(yaw)), 0.0f, float(std::cos(yaw))};
}
}  // namespace

extern "C" {

__attribute__((visibility("default"))) void fake_fove_configure(std::uint64_t period_us, int fail_create,
                                                                int stay_disconnected) {
  g_period_us = period_us;
  g_fail_create = fail_create;
  g_stay_disconnected = stay_disconnected;
  g_frame = -1;
  g_fetched = -1;
}

__attribute__((visibility("default"))) std::int64_t fake_fove_frame() { return g_frame.load(); }

__attribute__((visibility("default"))) Fove_ErrorCode fove_createHeadset(Fove_ClientCapabilities caps,
                                                                        Fove_Headset** out) {
  if (!out) return Fove_ErrorCode_API_InvalidArgument;
  if (g_fail_create.load()) return Fove_ErrorCode_Connect_NotConnected;
  if ((int(caps) & int(Fove_ClientCapabilities_EyeTracking)) == 0) return Fove_ErrorCode_API_InvalidArgument;
  *out = new Fove_Headset_{};
  return Fove_ErrorCode_None;
}

__attribute__((visibility("default"))) Fove_ErrorCode fove_Headset_destroy(Fove_Headset* h) {
  delete h;
  return Fove_ErrorCode_None;
}

__attribute__((visibility("default"))) Fove_ErrorCode fove_Headset_waitForProcessedEyeFrame(Fove_Headset* h) {
  if (!h) return Fove_ErrorCode_API_InvalidArgument;
  std::this_thread::sleep_for(std::chrono::microseconds(g_period_us.load()));
  const std::int64_t k = ++g_frame;
  return disconnected(k) ? Fove_ErrorCode_Connect_NotConnected : Fove_ErrorCode_None;
}

__attribute__((visibility("default"))) Fove_ErrorCode fove_Headset_fetchEyeTrackingData(Fove_Headset* h,
                                                                                       Fove_FrameTimestamp* ts) {
  if (!h) return Fove_ErrorCode_API_InvalidArgument;
  const std::int64_t k = g_frame.load();
  if (k < 0) return Fove_ErrorCode_Data_NoUpdate;
  if (disconnected(k)) return Fove_ErrorCode_Connect_NotConnected;
  g_fetched = k;
  if (ts) {
    ts->id = std::uint64_t(1000 + k);
    ts->timestamp = 5'000'000 + std::uint64_t(std::llround(double(k) * 1e6 / 120.0));
  }
  return Fove_ErrorCode_None;
}

__attribute__((visibility("default"))) Fove_ErrorCode fove_Headset_getCombinedGazeRay(Fove_Headset* h,
                                                                                     Fove_Ray* out) {
  if (!h || !out) return Fove_ErrorCode_API_InvalidArgument;
  const std::int64_t k = g_fetched.load();
  if (k < 0) return Fove_ErrorCode_Data_NoUpdate;
  out->origin = {0.0f, 0.0f, 0.0f};
  out->direction = direction(k);
  if (blink(k) || dropout(k)) return Fove_ErrorCode_Data_Unreliable;
  return low_accuracy(k) ? Fove_ErrorCode_Data_LowAccuracy : Fove_ErrorCode_None;
}

__attribute__((visibility("default"))) Fove_ErrorCode fove_Headset_getGazeVector(Fove_Headset* h, Fove_Eye,
                                                                                Fove_Vec3* out) {
  if (!h || !out) return Fove_ErrorCode_API_InvalidArgument;
  const std::int64_t k = g_fetched.load();
  if (k < 0) return Fove_ErrorCode_Data_NoUpdate;
  *out = direction(k);
  if (blink(k) || dropout(k)) return Fove_ErrorCode_Data_Unreliable;
  return low_accuracy(k) ? Fove_ErrorCode_Data_LowAccuracy : Fove_ErrorCode_None;
}

__attribute__((visibility("default"))) Fove_ErrorCode fove_Headset_getEyeState(Fove_Headset* h, Fove_Eye,
                                                                              Fove_EyeState* out) {
  if (!h || !out) return Fove_ErrorCode_API_InvalidArgument;
  const std::int64_t k = g_fetched.load();
  if (k < 0) return Fove_ErrorCode_Data_NoUpdate;
  *out = blink(k) ? Fove_EyeState_Closed : dropout(k) ? Fove_EyeState_NotDetected : Fove_EyeState_Opened;
  return Fove_ErrorCode_None;
}

}  // extern "C"
