// Every object the runtime hands out, and the one global state behind a mutex.
// Handles are opaque ids (never reused within a process), looked up in maps, so
// a stale or foreign handle is XR_ERROR_HANDLE_INVALID instead of a crash.
#pragma once

#include <cstdint>
#include <deque>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "config.h"
#include "frame_capture.h"
#include "gaze_source.h"
#include "headset.h"
#include "motion_source.h"
#include "pose_math.h"
#include "sim_clock.h"
#include "vulkan_device.h"
#include "xr_includes.h"

namespace foveart::sim {

inline constexpr XrSystemId kSystemId = 1;
inline const int64_t kFramePeriodNs = headset().frame_period_ns();  // 14'285'714 (70 Hz)
inline constexpr uint32_t kMaxLayers = 16;

struct Instance;

struct Swapchain {
  uint64_t id = 0;
  XrSession session{};
  XrSwapchainCreateInfo info{};
  std::vector<SwapchainImage> images;
  bool is_depth = false;
  // Spec state: images acquired in order, at most one waited, released FIFO.
  std::deque<uint32_t> acquired;  // acquired, not yet released (front is the oldest)
  bool front_waited = false;
  uint32_t next_index = 0;
  uint32_t acquire_count = 0;  // total acquires (static swapchains allow one)
  int64_t last_released = -1;  // index of the newest released image, -1: none yet
};

enum class SpaceKind { Reference, Action };

struct Space {
  uint64_t id = 0;
  XrSession session{};
  SpaceKind kind = SpaceKind::Reference;
  XrReferenceSpaceType reference_type = XR_REFERENCE_SPACE_TYPE_LOCAL;
  XrAction action{};
  XrPath subaction_path = XR_NULL_PATH;
  Pose offset;
};

struct ActionSet {
  uint64_t id = 0;
  std::string name;
  std::string localized_name;
  uint32_t priority = 0;
  bool attached = false;
  std::vector<XrAction> actions;
};

struct Action {
  uint64_t id = 0;
  XrActionSet set{};
  std::string name;
  std::string localized_name;
  XrActionType type = XR_ACTION_TYPE_BOOLEAN_INPUT;
  std::vector<XrPath> subaction_paths;
  bool bound_to_eye_gaze = false;  // decided at xrAttachSessionActionSets
  bool active = false;             // after the last xrSyncActions
};

struct Session {
  uint64_t id = 0;
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;
  bool running = false;         // between xrBeginSession and xrEndSession
  bool exit_requested = false;  // by the app or by the frame budget
  bool synchronized_sent = false;
  VulkanDevice vk;
  // Frame loop.
  int64_t vsync_origin_ns = 0;
  int64_t last_vsync_index = -1;
  bool frame_waited = false;  // xrWaitFrame returned, xrBeginFrame not yet called
  bool frame_begun = false;   // xrBeginFrame called, xrEndFrame not yet
  int64_t predicted_display_ns = 0;
  uint64_t frames_ended = 0;
  // A pipelining app's next xrWaitFrame may return before this frame's xrEndFrame:
  // the waited frame's timing moves to `current` at xrBeginFrame.
  FrameTiming waited;
  FrameTiming current;
  std::vector<XrActionSet> attached_sets;
  bool eye_gaze_bound = false;
  std::unique_ptr<FrameCapture> capture;
  int64_t motion_origin_ns = 0;  // XrTime the scripted motion starts from (xrBeginSession)
};

struct Instance {
  uint64_t id = 0;
  Config config;
  SimClock clock{false};
  int64_t origin_ns = 0;  // XrTime at xrCreateInstance; gaze source origin
  GazeSource gaze;
  std::optional<MotionSource> motion;  // FOVEART_SIM_MOTION: drives head and gaze when set
  std::string application_name;
  bool ext_vulkan = false;
  bool ext_vulkan2 = false;
  bool ext_eye_gaze = false;
  bool ext_timespec = false;
  bool graphics_requirements_queried = false;
  VkInstance vk_instance = VK_NULL_HANDLE;  // made by xrCreateVulkanInstanceKHR
  std::deque<XrEventDataBuffer> events;
  // Paths: id - 1 indexes path_strings.
  std::vector<std::string> path_strings;
  std::unordered_map<std::string, XrPath> path_ids;
  // Suggested bindings per interaction profile: (action, binding path).
  std::map<XrPath, std::vector<std::pair<XrAction, XrPath>>> suggested;
};

// The single process-wide state. Every entry point locks `mutex` (xrWaitFrame
// drops it while it sleeps or waits for the previous frame's xrBeginFrame).
struct Runtime {
  std::mutex mutex;
  // Signalled whenever a session's frame order changes (xrBeginFrame, xrBeginSession,
  // xrEndSession, destruction): an xrWaitFrame blocked on an unbegun frame re-checks.
  std::condition_variable frame_order_changed;
  uint64_t next_id = 1;
  std::unique_ptr<Instance> instance;
  std::map<uint64_t, std::unique_ptr<Session>> sessions;
  std::map<uint64_t, std::unique_ptr<Space>> spaces;
  std::map<uint64_t, std::unique_ptr<Swapchain>> swapchains;
  std::map<uint64_t, std::unique_ptr<ActionSet>> action_sets;
  std::map<uint64_t, std::unique_ptr<Action>> actions;
};

Runtime& runtime();

template <class Handle>
uint64_t handle_id(Handle h) {
  return static_cast<uint64_t>(reinterpret_cast<uintptr_t>(h));
}
template <class Handle>
Handle to_handle(uint64_t id) {
  return reinterpret_cast<Handle>(static_cast<uintptr_t>(id));
}
template <class T, class Handle>
T* find(std::map<uint64_t, std::unique_ptr<T>>& map, Handle h) {
  auto it = map.find(handle_id(h));
  return it == map.end() ? nullptr : it->second.get();
}

Instance* find_instance(XrInstance h);

// Paths.
XrPath intern_path(Instance& inst, const std::string& s);
const std::string* path_string(const Instance& inst, XrPath p);

// Events and the session state machine (session.cpp).
void push_event(Instance& inst, const XrEventDataBuffer& event);
void set_session_state(Instance& inst, Session& s, XrSessionState state);

// Head pose and spaces (api_space.cpp). `session` gives the scripted motion its
// origin (null: the instance's).
Pose head_pose_in_local(const Instance& inst, const Session* session, int64_t time_ns);
// The eye tracker's sample at a time (the motion's, else the gaze source's), in the
// traces' head space (+z forward); sample_time_ns is the sample's XrTime.
GazeSample eye_tracker_sample(const Instance& inst, const Session* session, int64_t time_ns,
                              int64_t& sample_time_ns);
// Space pose in LOCAL at a time; false when it cannot be located (inactive action).
bool space_pose_in_local(Runtime& rt, const Space& space, int64_t time_ns, Pose& out,
                         int64_t* gaze_sample_ns);

// Each view's FOV: headset().eye_fov_rad (FOVE 0: 1280x1440 per eye, 95 deg
// horizontal, square pixels; eyes at -+IPD/2 = 32 mm).
XrFovf view_fov();

// Destroys everything a session owns (swapchains, spaces, Vulkan helpers).
void destroy_session_children(Runtime& rt, uint64_t session_id);

}  // namespace foveart::sim
