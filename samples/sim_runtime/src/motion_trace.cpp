#include "motion_trace.h"

#include <cmath>
#include <fstream>
#include <limits>

#include "gaze_provider/trace_csv.h"
#include "headset.h"

namespace foveart::sim {
namespace {

gaze::GazeSample trace_sample(const GazeSample& s, uint64_t frame_id) {
  gaze::GazeSample out;
  out.device_time_ns = s.offset_ns;
  out.host_time_ns = s.offset_ns;
  out.frame_id = frame_id;
  out.valid = s.valid;
  out.source = gaze::GazeSourceKind::simulated;
  out.eye_state = s.valid ? gaze::EyeState::open : gaze::EyeState::closed;
  out.confidence = s.valid ? 1.0F : 0.0F;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const gaze::Vec3f direction =
      s.valid ? gaze::Vec3f{s.direction.x, s.direction.y, s.direction.z} : gaze::Vec3f{nan, nan, nan};
  out.combined_direction = direction;
  gaze::EyeGaze* eyes[2] = {&out.left, &out.right};
  for (uint32_t e = 0; e < 2; ++e) {
    eyes[e]->valid = s.valid;
    eyes[e]->state = out.eye_state;
    eyes[e]->origin_m = {static_cast<float>(headset().eye_offset_x_m(e)), 0.0F, 0.0F};
    eyes[e]->direction = direction;
  }
  return out;
}

}  // namespace

std::size_t write_motion_gaze_trace(const MotionSource& motion, double duration_s, std::ostream& out) {
  gaze::TraceWriter writer(out);
  const int64_t end_ns = std::llround(std::max(duration_s, 0.0) * 1e9);
  std::size_t rows = 0;
  for (int64_t t = 0; t <= end_ns; t = motion.next_sample_ns(t)) {
    writer.write(trace_sample(motion.gaze_at(t), rows));
    ++rows;
  }
  return rows;
}

bool write_motion_gaze_trace_file(const MotionSource& motion, double duration_s, const std::string& path,
                                  std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = path + ": cannot open for writing";
    return false;
  }
  write_motion_gaze_trace(motion, duration_s, out);
  out.flush();
  if (!out) {
    *error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace foveart::sim
