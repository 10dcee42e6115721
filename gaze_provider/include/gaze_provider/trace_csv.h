// The gaze trace format (CSV with a header line).
//
// Required columns, first and in this order:
//   device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z
// device_time_us is decimal microseconds (fractions allowed: ns survive a round trip;
// any epoch, as long as the nanoseconds fit int64);
// gaze_* is the combined unit gaze direction in head space, +x right, +y up,
// +z forward (the FOVE convention of gaze_provider/gaze_sample.h: straight ahead is
// 0,0,1, 15 deg left and 10 deg up is about -0.255,0.174,0.951). Every trace uses this
// convention and is read by read_trace: replay, `gaze-diag report`, and the simulated
// OpenXR runtime (FOVEART_SIM_GAZE), which turns it into OpenXR VIEW space (-z forward)
// itself where it hands gaze out. valid is 0 or 1; an invalid row may carry
// nan directions. Optional columns, any order, after those:
//   host_time_us, eye_state (open|closed|not_detected), confidence,
//   left_valid, left_origin_x/y/z, left_x/y/z, right_valid, right_origin_x/y/z, right_x/y/z,
//   target_x, target_y, target_z   (calibration target direction, for accuracy)
// Unknown columns are ignored.
//
// Errors: the reader never throws or crashes on bad input. Structural errors (no
// header, wrong required columns, truncated rows, non-numeric fields, nan/inf in a
// valid direction) fail with the 1-based line number. Rows whose device time does not
// increase (duplicates, steps back) are skipped and counted: a recorder that repeats
// a frame should not make the rest of a trace unreadable.
#pragma once

#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "gaze_provider/gaze_sample.h"

namespace foveart::gaze {

struct TraceRow {
  GazeSample sample{};
  bool has_host_time = false;
  std::optional<Vec3f> target;  // calibration target direction
};

struct Trace {
  std::vector<TraceRow> rows;
  bool has_eye_state = false;
  bool has_targets = false;
  bool has_host_time = false;
  std::uint64_t skipped_non_monotonic = 0;
  std::size_t first_skipped_line = 0;  // 0 when none
};

struct TraceError {
  std::size_t line = 0;  // 1-based; 0 when the file could not be opened
  std::string message;
  std::string file;  // read_trace_file's path; empty for a stream
  // "FILE:LINE: message", as compilers write it (the parts it has).
  std::string to_string() const;
};

std::optional<Trace> read_trace(std::istream& in, TraceError* error);
std::optional<Trace> read_trace_file(const std::string& path, TraceError* error);

// Writes header + rows. Floats use enough digits to read back bit-identical.
class TraceWriter {
 public:
  explicit TraceWriter(std::ostream& out, bool with_targets = false);
  void write(const GazeSample& sample, const std::optional<Vec3f>& target = std::nullopt);
  bool ok() const { return out_.good(); }

 private:
  std::ostream& out_;
  bool with_targets_;
};

}  // namespace foveart::gaze
