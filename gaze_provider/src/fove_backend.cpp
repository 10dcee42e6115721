// FOVE backend: the FOVE client library, loaded at run time with dlopen.
//
// Error mapping (FoveAPI.h error codes):
//   Data_Unreliable / Data_NoUpdate / Data_Uncalibrated -> invalid sample
//   Data_LowAccuracy                                      -> valid, low confidence
//   Connect_NotConnected, Hardware_Disconnected, or isHardwareConnected == false
//                                                         -> status disconnected with reason;
//                                                            polling continues (reconnect)
#include <dlfcn.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "fove_c_api.h"
#include "gaze_provider/gaze_math.h"
#include "threaded_provider.h"

namespace foveart::gaze {
namespace {

const char* fove_error_name(Fove_ErrorCode e) noexcept {
  switch (e) {
    case Fove_ErrorCode_None: return "None";
    case Fove_ErrorCode_Connect_NotConnected: return "Connect_NotConnected";
    case Fove_ErrorCode_API_InvalidArgument: return "API_InvalidArgument";
    case Fove_ErrorCode_API_NotRegistered: return "API_NotRegistered";
    case Fove_ErrorCode_API_Timeout: return "API_Timeout";
    case Fove_ErrorCode_Data_Unreadable: return "Data_Unreadable";
    case Fove_ErrorCode_Data_NoUpdate: return "Data_NoUpdate";
    case Fove_ErrorCode_Data_Uncalibrated: return "Data_Uncalibrated";
    case Fove_ErrorCode_Data_Unreliable: return "Data_Unreliable";
    case Fove_ErrorCode_Data_LowAccuracy: return "Data_LowAccuracy";
    case Fove_ErrorCode_Hardware_Disconnected: return "Hardware_Disconnected";
    case Fove_ErrorCode_UnknownError: return "UnknownError";
    default: return "unlisted error";
  }
}

EyeState map_eye_state(Fove_EyeState s) noexcept {
  switch (s) {
    case Fove_EyeState_Opened: return EyeState::open;
    case Fove_EyeState_Closed: return EyeState::closed;
    default: return EyeState::not_detected;
  }
}

struct FoveApi {
  void* lib = nullptr;
  PFN_fove_createHeadset create = nullptr;
  PFN_fove_Headset_destroy destroy = nullptr;
  PFN_fove_Headset_fetchEyeTrackingData fetch = nullptr;
  PFN_fove_Headset_getGazeVector gaze_vector = nullptr;
  PFN_fove_Headset_getCombinedGazeRay combined_ray = nullptr;
  PFN_fove_Headset_getEyeState eye_state = nullptr;
  PFN_fove_Headset_waitForProcessedEyeFrame wait = nullptr;          // optional
  PFN_fove_Headset_isHardwareConnected hardware_connected = nullptr; // optional
};

template <typename F>
bool load(void* lib, const char* name, F& out, std::string* missing) {
  out = reinterpret_cast<F>(dlsym(lib, name));
  if (!out && missing) *missing += std::string(missing->empty() ? "" : ", ") + name;
  return out != nullptr;
}

class FoveBackend final : public detail::Backend {
 public:
  FoveBackend(FoveApi api, Fove_Headset* headset, const FoveConfig& config)
      : api_(api), headset_(headset), config_(config) {}
  ~FoveBackend() override {
    if (headset_) api_.destroy(headset_);
    if (api_.lib) dlclose(api_.lib);
  }

  detail::PollResult poll(GazeSample& out, std::string& reason) noexcept override {
    Fove_ErrorCode e = Fove_ErrorCode_None;
    if (api_.wait) {
      e = api_.wait(headset_);  // blocks until the next 120 Hz eye frame (service timeout applies)
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (e == Fove_ErrorCode_Connect_NotConnected || e == Fove_ErrorCode_Hardware_Disconnected)
      return disconnected(e, reason);
    if (api_.hardware_connected) {
      bool connected = true;
      if (api_.hardware_connected(headset_, &connected) == Fove_ErrorCode_None && !connected) {
        reason = "FOVE headset hardware disconnected (isHardwareConnected = false)";
        return detail::PollResult::disconnected;
      }
    }
    Fove_FrameTimestamp ts{};
    e = api_.fetch(headset_, &ts);
    if (e == Fove_ErrorCode_Connect_NotConnected || e == Fove_ErrorCode_Hardware_Disconnected)
      return disconnected(e, reason);
    if (e != Fove_ErrorCode_None && e != Fove_ErrorCode_Data_NoUpdate) {
      if (!api_.wait) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      return detail::PollResult::none;
    }
    if (have_frame_ && ts.id == last_id_) return detail::PollResult::none;  // no new eye frame
    have_frame_ = true;
    last_id_ = ts.id;

    out = GazeSample{};
    out.source = GazeSourceKind::fove;
    out.frame_id = ts.id;
    out.device_time_ns = static_cast<std::int64_t>(ts.timestamp) * 1000;

    Fove_Ray ray{};
    const Fove_ErrorCode ray_e = api_.combined_ray(headset_, &ray);
    const Vec3f dir{ray.direction.x, ray.direction.y, ray.direction.z};
    if ((ray_e == Fove_ErrorCode_None || ray_e == Fove_ErrorCode_Data_LowAccuracy) && is_finite(dir) &&
        length(dir) > 1e-6) {
      out.valid = true;
      out.combined_direction = normalized(dir);
      out.confidence = ray_e == Fove_ErrorCode_None ? 1.0f : config_.low_accuracy_confidence;
    }
    int open = 0, closed = 0;
    for (int i = 0; i < 2; ++i) {
      EyeGaze& eye = i == 0 ? out.left : out.right;
      const Fove_Eye which = i == 0 ? Fove_Eye_Left : Fove_Eye_Right;
      Fove_EyeState st = Fove_EyeState_NotDetected;
      if (api_.eye_state(headset_, which, &st) == Fove_ErrorCode_None) eye.state = map_eye_state(st);
      Fove_Vec3 v{};
      const Fove_ErrorCode ve = api_.gaze_vector(headset_, which, &v);
      const Vec3f d{v.x, v.y, v.z};
      eye.valid = (ve == Fove_ErrorCode_None || ve == Fove_ErrorCode_Data_LowAccuracy) && is_finite(d) &&
                  length(d) > 1e-6;
      if (eye.valid) eye.direction = normalized(d);
      open += eye.state == EyeState::open;
      closed += eye.state == EyeState::closed;
    }
    out.eye_state = open > 0 ? EyeState::open : closed > 0 ? EyeState::closed : EyeState::not_detected;
    if (out.eye_state != EyeState::open) out.valid = false;
    if (!out.valid) out.confidence = 0.0f;
    return detail::PollResult::sample;
  }

  GazeSourceKind kind() const noexcept override { return GazeSourceKind::fove; }
  double nominal_rate_hz() const noexcept override { return 120.0; }

 private:
  detail::PollResult disconnected(Fove_ErrorCode e, std::string& reason) noexcept {
    reason = e == Fove_ErrorCode_Hardware_Disconnected
                 ? "FOVE headset hardware disconnected (Hardware_Disconnected)"
                 : "not connected to the FOVE service (Connect_NotConnected)";
    have_frame_ = false;
    if (!api_.wait) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return detail::PollResult::disconnected;
  }

  FoveApi api_;
  Fove_Headset* headset_;
  FoveConfig config_;
  bool have_frame_ = false;
  std::uint64_t last_id_ = 0;
};

}  // namespace

std::string fove_library_path(const FoveConfig& config) {
  if (!config.library_path.empty()) return config.library_path;
  if (const char* env = std::getenv("FOVEART_FOVE_LIBRARY"); env && *env) return env;
  return "libFoveClient.so";
}

std::unique_ptr<GazeProvider> create_fove_provider(const FoveConfig& fove, const ProviderOptions& options,
                                                   std::string* error) {
  auto fail = [&](std::string message) -> std::unique_ptr<GazeProvider> {
    if (error) *error = "fove: " + std::move(message);
    return nullptr;
  };
  const std::string path = fove_library_path(fove);
  FoveApi api;
  api.lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!api.lib) {
    const char* why = dlerror();
    return fail("cannot load the FOVE client library '" + path + "': " + (why ? why : "unknown error") +
                " (set FOVEART_FOVE_LIBRARY or FoveConfig::library_path)");
  }
  std::string missing;
  bool ok = load(api.lib, "fove_createHeadset", api.create, &missing);
  ok &= load(api.lib, "fove_Headset_destroy", api.destroy, &missing);
  ok &= load(api.lib, "fove_Headset_fetchEyeTrackingData", api.fetch, &missing);
  ok &= load(api.lib, "fove_Headset_getGazeVector", api.gaze_vector, &missing);
  ok &= load(api.lib, "fove_Headset_getCombinedGazeRay", api.combined_ray, &missing);
  ok &= load(api.lib, "fove_Headset_getEyeState", api.eye_state, &missing);
  load(api.lib, "fove_Headset_waitForProcessedEyeFrame", api.wait, nullptr);
  load(api.lib, "fove_Headset_isHardwareConnected", api.hardware_connected, nullptr);
  if (!ok) {
    dlclose(api.lib);
    return fail("'" + path + "' lacks FOVE C API entry points: " + missing);
  }
  Fove_Headset* headset = nullptr;
  const Fove_ErrorCode e = api.create(Fove_ClientCapabilities_EyeTracking, &headset);
  if (e != Fove_ErrorCode_None || !headset) {
    dlclose(api.lib);
    return fail(std::string("fove_createHeadset(EyeTracking) failed: ") + fove_error_name(e) + " (" +
                std::to_string(int(e)) + ")");
  }
  return std::make_unique<detail::ThreadedProvider>(std::make_unique<FoveBackend>(api, headset, fove), options);
}

}  // namespace foveart::gaze
