#include "gaze_source.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "gaze_provider/trace_csv.h"
#include "headset.h"

namespace foveart::sim {
namespace {

int64_t gaze_period_ns() { return headset().gaze_period_ns(); }  // 8'333'333 (120 Hz)

constexpr int64_t kFixationNs = 400'000'000;
constexpr int64_t kSaccadeNs = 40'000'000;
constexpr int64_t kBlinkNs = 200'000'000;

struct Target {
  float azimuth_deg;
  float elevation_deg;
};
constexpr std::array<Target, 5> kTargets{
    {{0.0F, 0.0F}, {12.0F, 6.0F}, {-15.0F, -5.0F}, {6.0F, -12.0F}, {-8.0F, 10.0F}}};
constexpr int64_t kCycleNs =
    static_cast<int64_t>(kTargets.size()) * (kFixationNs + kSaccadeNs) + kBlinkNs;

// Head space, +z forward: azimuth positive to the right, elevation positive up
// (yaw = atan2(x, z), pitch = atan2(y, hypot(x, z)), gaze_provider/gaze_sample.h).
glm::vec3 direction_from_angles(float azimuth_deg, float elevation_deg) {
  const float az = glm::radians(azimuth_deg);
  const float el = glm::radians(elevation_deg);
  return {std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
}

}  // namespace

GazeSample saccade_script_sample(int64_t offset_ns) {
  const int64_t sample_ns = (std::max<int64_t>(offset_ns, 0) / gaze_period_ns()) * gaze_period_ns();
  const int64_t in_cycle = sample_ns % kCycleNs;
  GazeSample s;
  s.offset_ns = sample_ns;
  const int64_t segment = kFixationNs + kSaccadeNs;
  const int64_t index = in_cycle / segment;
  if (index >= static_cast<int64_t>(kTargets.size())) {  // blink at the end of the cycle
    s.valid = false;
    s.direction = direction_from_angles(kTargets[0].azimuth_deg, kTargets[0].elevation_deg);
    return s;
  }
  const Target& from = kTargets[static_cast<size_t>(index)];
  const Target& to = kTargets[static_cast<size_t>(index + 1) % kTargets.size()];
  const int64_t t = in_cycle % segment;
  float az = from.azimuth_deg;
  float el = from.elevation_deg;
  if (t >= kFixationNs) {  // saccade: linear in angle over 40 ms
    const float u = static_cast<float>(t - kFixationNs) / static_cast<float>(kSaccadeNs);
    az += u * (to.azimuth_deg - from.azimuth_deg);
    el += u * (to.elevation_deg - from.elevation_deg);
  }
  s.valid = true;
  s.direction = direction_from_angles(az, el);
  return s;
}

GazeSource GazeSource::saccade_script() {
  return GazeSource{};
}

std::optional<GazeSource> GazeSource::from_trace_file(const std::string& path, std::string* error) {
  gaze::TraceError trace_error;
  const std::optional<gaze::Trace> trace = gaze::read_trace_file(path, &trace_error);
  if (!trace) {
    *error = trace_error.to_string();
    return std::nullopt;
  }
  if (trace->rows.empty()) {
    *error = path + ": the trace has a header but no samples";
    return std::nullopt;
  }
  GazeSource source;
  source.skipped_rows_ = trace->skipped_non_monotonic;
  const int64_t first_ns = trace->rows.front().sample.device_time_ns;
  for (const gaze::TraceRow& row : trace->rows) {
    const gaze::GazeSample& in = row.sample;
    GazeSample s;
    s.offset_ns = in.device_time_ns - first_ns;
    s.valid = in.valid;  // the reader guarantees a finite, non-zero direction when valid
    if (s.valid) {
      s.direction = glm::normalize(
          glm::vec3(in.combined_direction.x, in.combined_direction.y, in.combined_direction.z));
    }
    source.trace_.push_back(s);
  }
  // Loop length: last sample time plus one nominal sample period.
  source.trace_period_ns_ = source.trace_.back().offset_ns + gaze_period_ns();
  return source;
}

GazeSample GazeSource::sample_at(int64_t offset_ns) const {
  if (trace_.empty()) return saccade_script_sample(offset_ns);
  const int64_t t = std::max<int64_t>(offset_ns, 0);
  const int64_t loop = t / trace_period_ns_;
  const int64_t in_loop = t % trace_period_ns_;
  auto it =
      std::upper_bound(trace_.begin(), trace_.end(), in_loop,
                       [](int64_t value, const GazeSample& s) { return value < s.offset_ns; });
  GazeSample s = (it == trace_.begin()) ? trace_.front() : *std::prev(it);
  s.offset_ns += loop * trace_period_ns_;
  return s;
}

}  // namespace foveart::sim
