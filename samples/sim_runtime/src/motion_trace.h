// The eye tracker's side of a scripted motion as a gaze trace (gaze_provider/trace_csv.h,
// written by the provider's own writer): what the runtime's eye gaze pose shows under
// FOVEART_SIM_MOTION, row for row, so the gaze provider (`replay:FILE`) can play the
// same gaze with its own saccade detector and blink hold while the runtime plays the head.
//
// Rows: every eye-tracker sample of the motion (MotionSource::gaze_at, next_sample_ns)
// from 0 to duration_s, looping as in the runtime; device_time_us = the sample's offset (first row
// 0), +z forward, invalid rows (blinks) with nan directions and eye_state closed, both
// eyes at -+IPD/2 looking along the combined gaze.
#pragma once

#include <ostream>
#include <string>

#include "motion_source.h"

namespace foveart::sim {

// Returns the number of rows written.
std::size_t write_motion_gaze_trace(const MotionSource& motion, double duration_s, std::ostream& out);
// To a file; false and a message naming the file when it cannot be written.
[[nodiscard]] bool write_motion_gaze_trace_file(const MotionSource& motion, double duration_s, const std::string& path,
                                  std::string* error);

}  // namespace foveart::sim
