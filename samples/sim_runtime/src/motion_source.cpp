#include "motion_source.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>

#include "headset.h"

namespace foveart::sim {

MotionSource::MotionSource(motion::ScriptedMotion motion, std::string name)
    : motion_(std::make_shared<const motion::ScriptedMotion>(std::move(motion))),
      name_(std::move(name)) {
  if (!motion_->samples().empty()) {
    const double span_s = motion_->samples().back().time_s - motion_->samples().front().time_s;
    period_ns_ = std::max<int64_t>(0, std::llround(span_s * 1e9));
  }
  const int64_t gaze_period_ns = headset().gaze_period_ns();
  samples_per_loop_ = std::max<int64_t>(
      1, std::llround(static_cast<double>(period_ns_) / static_cast<double>(gaze_period_ns)));
}

std::optional<MotionSource> MotionSource::from_spec(const std::string& spec, uint64_t seed,
                                                    std::string* error) {
  if (spec == "builtin") return MotionSource(motion::builtin_motion(seed), "builtin (seed " + std::to_string(seed) + ")");
  std::optional<motion::ScriptedMotion> motion = motion::load_motion_csv(spec, error);
  if (!motion) return std::nullopt;
  return MotionSource(std::move(*motion), spec);
}

void MotionSource::split(int64_t offset_ns, int64_t& loop_start_ns, int64_t& in_loop_ns) const {
  const int64_t t = std::max<int64_t>(offset_ns, 0);
  if (period_ns_ <= 0) {
    loop_start_ns = t;
    in_loop_ns = 0;
    return;
  }
  in_loop_ns = t % period_ns_;
  loop_start_ns = t - in_loop_ns;
}

double MotionSource::script_time_s(int64_t in_loop_ns) const {
  return motion_->samples().front().time_s + static_cast<double>(in_loop_ns) * 1e-9;
}

Pose MotionSource::head_in_local(int64_t offset_ns) const {
  int64_t loop_start_ns = 0;
  int64_t in_loop_ns = 0;
  split(offset_ns, loop_start_ns, in_loop_ns);
  const motion::MotionSample s = motion_->at(script_time_s(in_loop_ns));
  const foveation::EyePose local = motion::head_pose_above_standing_eye(s);
  Pose p;
  p.orientation = local.orientation;
  p.position = local.position_m;
  return p;
}

GazeSample MotionSource::gaze_at(int64_t offset_ns) const {
  int64_t loop_start_ns = 0;
  int64_t in_loop_ns = 0;
  split(offset_ns, loop_start_ns, in_loop_ns);
  const int64_t period_ns = headset().gaze_period_ns();
  const int64_t index = period_ns_ > 0 ? std::min(in_loop_ns / period_ns, samples_per_loop_ - 1) : 0;
  const int64_t sample_in_loop_ns = index * period_ns;
  const motion::MotionSample s = motion_->at(script_time_s(sample_in_loop_ns));
  GazeSample out;
  out.offset_ns = loop_start_ns + sample_in_loop_ns;
  out.valid = s.gaze_valid;
  // The script looks along -z; traces (and GazeSample) along +z: flip z.
  out.direction = glm::normalize(glm::vec3(s.gaze_head.x, s.gaze_head.y, -s.gaze_head.z));
  return out;
}

int64_t MotionSource::next_sample_ns(int64_t sample_offset_ns) const {
  const int64_t period_ns = headset().gaze_period_ns();
  if (period_ns_ <= 0) return sample_offset_ns + period_ns;
  int64_t loop_start_ns = 0;
  int64_t in_loop_ns = 0;
  split(sample_offset_ns, loop_start_ns, in_loop_ns);
  const int64_t index = in_loop_ns / period_ns + 1;
  return index < samples_per_loop_ ? loop_start_ns + index * period_ns : loop_start_ns + period_ns_;
}

}  // namespace foveart::sim
