// Where the simulated eye tracker's gaze comes from: a recorded trace in the
// gaze-diag CSV format or a built-in saccade script. Gaze is the combined unit
// direction in head space (+x right, +y up, -z forward, as OpenXR's VIEW space).
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
  glm::vec3 direction{0.0F, 0.0F, -1.0F};
};

class GazeSource {
 public:
  // Built-in script: fixations 440 ms apart joined by 40 ms saccades, and a
  // 200 ms blink (invalid samples) once per 2.4 s cycle. Samples at 120 Hz.
  static GazeSource saccade_script();
  // gaze-diag CSV: header line starting with the columns
  //   device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z
  // (further columns are ignored). '#' lines and empty lines are skipped.
  // Sample times are device_time_us minus the first row's. The trace loops.
  // Returns nullopt and a "file:line: what" message on malformed input.
  static std::optional<GazeSource> from_csv_file(const std::string& path, std::string& error);

  // The newest sample whose time is <= offset_ns (offset_ns >= 0).
  GazeSample sample_at(int64_t offset_ns) const;

  size_t trace_size() const { return trace_.size(); }

 private:
  std::vector<GazeSample> trace_;  // empty: the built-in script
  int64_t trace_period_ns_ = 0;    // loop length for traces
};

// The built-in script's gaze at a time (exposed for tests and docs).
GazeSample saccade_script_sample(int64_t offset_ns);

}  // namespace foveart::sim
