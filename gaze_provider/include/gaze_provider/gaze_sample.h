// GazeSample: one eye-tracker measurement, as every backend delivers it.
//
// Conventions (the whole module):
//  - Head space, FOVE convention: +x right, +y up, +z forward (left-handed). A gaze
//    direction is a unit vector; straight ahead is (0, 0, 1).
//  - Angles: yaw = atan2(x, z) (positive to the right), pitch = atan2(y, hypot(x, z))
//    (positive up); names say degrees (`_deg`), everything else is radians.
//  - Time: int64 nanoseconds. `host_time_ns` is std::chrono::steady_clock; the device
//    clock (`device_time_ns`) has its own epoch unless a backend says otherwise.
#pragma once

#include <cstdint>
#include <type_traits>

namespace foveart::gaze {

struct Vec3f {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
};

enum class EyeState : std::uint8_t { open = 0, closed = 1, not_detected = 2 };

enum class GazeSourceKind : std::uint8_t { simulated = 0, replay = 1, fove = 2, hid = 3 };

const char* to_string(EyeState state) noexcept;
const char* to_string(GazeSourceKind kind) noexcept;

// One eye. `origin_m` is the eye position in head space (metres), zero when unknown.
// In filtered/predicted samples a valid eye's direction is moved with the combined
// direction (same yaw/pitch change), so per-eye gaze is smoothed and predicted too;
// held samples (blinks) carry invalid eyes: use combined_direction then.
struct EyeGaze {
  Vec3f origin_m{};
  Vec3f direction{0.0f, 0.0f, 1.0f};
  bool valid = false;
  EyeState state = EyeState::not_detected;
};

struct GazeSample {
  // -- as measured --------------------------------------------------------------
  std::int64_t device_time_ns = 0;  // capture time on the device clock
  std::uint64_t frame_id = 0;       // device frame counter; gaps mean dropped frames
  std::int64_t host_time_ns = 0;    // steady_clock time the host received the sample
  EyeGaze left{};
  EyeGaze right{};
  Vec3f combined_direction{0.0f, 0.0f, 1.0f};  // unit vector, meaningful when `valid`
  bool valid = false;                          // combined direction usable
  EyeState eye_state = EyeState::not_detected; // both eyes summarised
  float confidence = 0.0f;                     // 0..1
  GazeSourceKind source = GazeSourceKind::simulated;

  // -- set by the filter chain (false/0 on raw samples) -------------------------
  bool in_saccade = false;         // velocity above the saccade threshold
  bool held = false;               // direction reused from the last valid sample
  bool lost = false;               // invalid for longer than the hold time
  bool extrapolated = false;       // predicted beyond the last measurement
  std::int64_t saccade_onset_device_ns = 0;  // onset of the current/last saccade, 0 if none
  std::int64_t hold_onset_device_ns = 0;     // first sample of the current/last hold, 0 if none
};

static_assert(std::is_trivially_copyable_v<GazeSample>, "GazeSample is published lock-free");

}  // namespace foveart::gaze
