// Where the simulated eye tracker's gaze comes from: a recorded trace in the gaze
// provider's format, read by the provider's own reader (gaze_provider/trace_csv.h,
// what `gaze-diag stream --record` writes), or a built-in saccade script.
//
// Directions here are in the gaze provider's head space: +x right, +y up, +z forward
// (gaze_provider/gaze_sample.h), the one convention of every gaze trace. They become
// OpenXR VIEW space (-z forward) only where the runtime hands gaze to the app, through
// openxr_view_direction().
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

namespace foveart::sim {

struct GazeSample {
  int64_t offset_ns = 0;  // since the gaze source's origin (XrTime of xrCreateInstance)
  bool valid = false;
  glm::vec3 direction{0.0F, 0.0F, 1.0F};  // unit, head space, +z forward
};

class GazeSource {
 public:
  // Built-in script: fixations 440 ms apart joined by 40 ms saccades, and a
  // 200 ms blink (invalid samples) once per 2.4 s cycle. Samples at the headset's
  // eye-tracker rate (120 Hz).
  static GazeSource saccade_script();
  // A trace file (gaze_provider/trace_csv.h). Sample times are device_time_us minus
  // the first row's; the trace loops. Rows whose device time does not increase are
  // skipped (skipped_rows()), as the provider's reader does. Returns nullopt and the
  // reader's message (file and line) on malformed input or a trace without rows.
  static std::optional<GazeSource> from_trace_file(const std::string& path, std::string* error);

  // The newest sample whose time is <= offset_ns (offset_ns >= 0).
  GazeSample sample_at(int64_t offset_ns) const;

  size_t trace_size() const { return trace_.size(); }
  uint64_t skipped_rows() const { return skipped_rows_; }

 private:
  std::vector<GazeSample> trace_;  // empty: the built-in script
  int64_t trace_period_ns_ = 0;    // loop length for traces
  uint64_t skipped_rows_ = 0;
};

// The built-in script's gaze at a time (exposed for tests and docs).
GazeSample saccade_script_sample(int64_t offset_ns);

// Head space (+z forward, the traces' convention) to OpenXR VIEW space (-z forward):
// x right and y up agree, z flips.
inline glm::vec3 openxr_view_direction(const glm::vec3& head_direction) {
  return {head_direction.x, head_direction.y, -head_direction.z};
}

}  // namespace foveart::sim
