#include "gaze_source.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <sstream>

#include "sim_runtime/sim_env.h"

namespace foveart::sim {
namespace {

constexpr int64_t kGazePeriodNs = static_cast<int64_t>(1e9 / env::kGazeRateHz);
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

glm::vec3 direction_from_angles(float azimuth_deg, float elevation_deg) {
  const float az = glm::radians(azimuth_deg);
  const float el = glm::radians(elevation_deg);
  return {std::sin(az) * std::cos(el), std::sin(el), -std::cos(az) * std::cos(el)};
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
    while (!cell.empty() && cell.front() == ' ') cell.erase(cell.begin());
    out.push_back(cell);
  }
  return out;
}

bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return errno == 0 && end == s.c_str() + s.size() && std::isfinite(out);
}

}  // namespace

GazeSample saccade_script_sample(int64_t offset_ns) {
  const int64_t sample_ns = (std::max<int64_t>(offset_ns, 0) / kGazePeriodNs) * kGazePeriodNs;
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

std::optional<GazeSource> GazeSource::from_csv_file(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = path + ": cannot open gaze trace";
    return std::nullopt;
  }
  static const std::array<const char*, 6> kColumns{"device_time_us", "frame_id", "valid",
                                                   "gaze_x",         "gaze_y",   "gaze_z"};
  GazeSource source;
  std::string line;
  size_t line_no = 0;
  bool have_header = false;
  double first_us = 0.0;
  double last_us = 0.0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    if (line.empty() || line == "\r" || line[0] == '#') continue;
    const auto cells = split_csv(line);
    if (!have_header) {
      for (size_t i = 0; i < kColumns.size(); ++i) {
        if (i >= cells.size() || cells[i] != kColumns[i]) {
          error =
              where +
              "header must start with device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z (column " +
              std::to_string(i + 1) + " is '" + (i < cells.size() ? cells[i] : std::string()) +
              "')";
          return std::nullopt;
        }
      }
      have_header = true;
      continue;
    }
    if (cells.size() < kColumns.size()) {
      error = where + "expected at least 6 columns, found " + std::to_string(cells.size());
      return std::nullopt;
    }
    std::array<double, 6> v{};
    for (size_t i = 0; i < kColumns.size(); ++i) {
      if (!parse_double(cells[i], v[i])) {
        error = where + "column " + kColumns[i] + " is not a number: '" + cells[i] + "'";
        return std::nullopt;
      }
    }
    if (v[2] != 0.0 && v[2] != 1.0) {
      error = where + "column valid must be 0 or 1, found '" + cells[2] + "'";
      return std::nullopt;
    }
    if (source.trace_.empty()) first_us = v[0];
    if (v[0] < last_us && !source.trace_.empty()) {
      error = where + "device_time_us goes backwards (" + cells[0] + ")";
      return std::nullopt;
    }
    last_us = v[0];
    GazeSample s;
    s.offset_ns = static_cast<int64_t>(std::llround((v[0] - first_us) * 1000.0));
    s.valid = v[2] == 1.0;
    const glm::vec3 d(static_cast<float>(v[3]), static_cast<float>(v[4]), static_cast<float>(v[5]));
    const float len = glm::length(d);
    if (s.valid) {
      if (!(len > 1e-6F)) {
        error = where + "valid sample with a zero gaze direction";
        return std::nullopt;
      }
      s.direction = d / len;
    }
    source.trace_.push_back(s);
  }
  if (!have_header) {
    error = path + ": empty gaze trace (no header)";
    return std::nullopt;
  }
  if (source.trace_.empty()) {
    error = path + ": gaze trace has a header but no samples";
    return std::nullopt;
  }
  // Loop length: last sample time plus one nominal sample period.
  source.trace_period_ns_ = source.trace_.back().offset_ns + kGazePeriodNs;
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
