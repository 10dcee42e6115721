#include <motion/scripted_motion.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <foveation/input_file.hpp>

namespace foveart::motion {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Deterministic uniform in [0, 1) from (seed, stream, index): SplitMix64.
double uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + stream * 0xBF58476D1CE4E5B9ull + index + 0x94D049BB133111EBull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return double(z >> 11) * 0x1.0p-53;
}

// Gaze direction (head space, -z forward) at yaw / pitch in degrees.
glm::vec3 gaze_at(double yaw_deg, double pitch_deg) {
  const double y = yaw_deg * kDeg, p = pitch_deg * kDeg;
  return glm::normalize(glm::vec3(float(std::sin(y) * std::cos(p)), float(std::sin(p)),
                                  float(-std::cos(y) * std::cos(p))));
}

}  // namespace

ScriptedMotion::ScriptedMotion(std::vector<MotionSample> samples) : samples_(std::move(samples)) {
  if (samples_.empty()) throw std::invalid_argument("scripted motion: no samples");
  for (std::size_t i = 1; i < samples_.size(); ++i) {
    if (!(samples_[i].time_s > samples_[i - 1].time_s)) {
      throw std::invalid_argument("scripted motion: sample " + std::to_string(i) + " does not come after the one before");
    }
  }
}

MotionSample ScriptedMotion::at(double time_s) const {
  if (samples_.empty()) return {};
  if (!(time_s > samples_.front().time_s)) return samples_.front();
  if (time_s >= samples_.back().time_s) return samples_.back();
  const auto next = std::upper_bound(samples_.begin(), samples_.end(), time_s,
                                     [](double t, const MotionSample& s) { return t < s.time_s; });
  const MotionSample& a = *(next - 1);
  const MotionSample& b = *next;
  const float f = float((time_s - a.time_s) / (b.time_s - a.time_s));
  MotionSample s = a;
  s.time_s = time_s;
  s.head_orientation = glm::slerp(a.head_orientation, b.head_orientation, f);
  s.head_position_m = glm::mix(a.head_position_m, b.head_position_m, f);
  s.gaze_head = glm::normalize(glm::mix(a.gaze_head, b.gaze_head, f));
  return s;
}

ScriptedMotion builtin_motion(std::uint64_t seed) {
  constexpr double kRate = 1000.0, kDuration = 4.0;
  constexpr double kSaccadeAt = 1.5, kSaccadeS = 0.045, kBlinkAt = 3.0, kBlinkS = 0.15;
  // Fixation targets (head space, degrees) and microsaccade times, drawn once.
  struct Event {
    double time_s, yaw_deg, pitch_deg;
  };
  std::vector<Event> fixations;  // each fixation's start and target
  double t = 0.0;
  std::uint64_t i = 0;
  double yaw = 0.0, pitch = 0.0;
  while (t < kDuration) {
    fixations.push_back({t, yaw, pitch});
    t += 0.4 + 0.2 * uniform(seed, 1, i);
    if (t > kSaccadeAt && fixations.back().time_s < kSaccadeAt) {
      t = kSaccadeAt;  // the big saccade starts a fixation 12 deg away
      yaw += 12.0, pitch -= 2.0;
    } else {
      // A microsaccade: 0.15-0.4 deg in a random direction.
      const double a = 2.0 * std::numbers::pi * uniform(seed, 2, i), r = 0.15 + 0.25 * uniform(seed, 3, i);
      yaw += r * std::cos(a), pitch += r * std::sin(a);
    }
    ++i;
  }
  std::vector<MotionSample> samples;
  samples.reserve(std::size_t(kRate * kDuration) + 1);
  double head_yaw_deg = 0.0;
  for (std::size_t n = 0; n <= std::size_t(kRate * kDuration); ++n) {
    const double ts = double(n) / kRate;
    MotionSample s;
    s.time_s = ts;
    // Head: yaw rate 20 +- 10 deg/s, tremor in yaw and pitch, a little translation.
    head_yaw_deg += (20.0 + 10.0 * std::sin(2.0 * std::numbers::pi * ts / kDuration)) / kRate;
    const double tremor_yaw = 0.15 * std::sin(2.0 * std::numbers::pi * 9.0 * ts);
    const double tremor_pitch = 0.10 * std::sin(2.0 * std::numbers::pi * 11.0 * ts + 1.0);
    s.head_orientation = glm::angleAxis(float(-(head_yaw_deg + tremor_yaw) * kDeg), glm::vec3(0, 1, 0)) *
                         glm::angleAxis(float(tremor_pitch * kDeg), glm::vec3(1, 0, 0));
    s.head_position_m = {float(0.0005 * std::sin(2.0 * std::numbers::pi * 7.0 * ts)), kStandingEyeHeightM, 0.0f};
    // Gaze: the current fixation, moving there over 25 ms (microsaccade) or 45 ms (the saccade).
    std::size_t f = 0;
    while (f + 1 < fixations.size() && fixations[f + 1].time_s <= ts) ++f;
    const Event& to = fixations[f];
    const Event& from = f > 0 ? fixations[f - 1] : to;
    const bool big = std::abs(to.time_s - kSaccadeAt) < 1e-9;
    const double move_s = big ? kSaccadeS : 0.025;
    const double u = std::clamp((ts - to.time_s) / move_s, 0.0, 1.0);
    const double ease = u * u * (3.0 - 2.0 * u);
    const double drift = 0.5 * (ts - to.time_s);  // deg, along +yaw
    double gy = from.yaw_deg + (to.yaw_deg - from.yaw_deg) * ease + (u >= 1.0 ? drift : 0.0);
    double gp = from.pitch_deg + (to.pitch_deg - from.pitch_deg) * ease;
    // Tracker noise, 0.05 deg rms per axis (uniform of the same variance).
    gy += 0.05 * std::sqrt(12.0) * (uniform(seed, 4, n) - 0.5);
    gp += 0.05 * std::sqrt(12.0) * (uniform(seed, 5, n) - 0.5);
    s.gaze_head = gaze_at(gy, gp);
    s.saccade = big && u < 1.0 && ts >= to.time_s;
    s.gaze_valid = !(ts >= kBlinkAt && ts < kBlinkAt + kBlinkS);
    samples.push_back(s);
  }
  return ScriptedMotion(std::move(samples));
}

std::optional<ScriptedMotion> load_motion_csv(const std::filesystem::path& path, std::string* error) {
  const auto fail = [&](std::string message) -> std::optional<ScriptedMotion> {
    *error = std::move(message);
    return std::nullopt;
  };
  if (const std::string problem = foveation::input_file_problem(path); !problem.empty())
    return fail(path.string() + ": " + problem);
  std::ifstream in(path);
  if (!in) return fail(path.string() + ": cannot open the motion script");
  std::string line;
  std::getline(in, line);
  if (line.rfind("time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid", 0) != 0) {
    return fail(path.string() + ":1: expected the header time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid[,saccade]");
  }
  std::vector<MotionSample> samples;
  for (int line_no = 2; std::getline(in, line); ++line_no) {
    if (line.empty()) continue;
    std::vector<double> v;
    std::stringstream cells(line);
    std::string cell;
    for (int col = 1; std::getline(cells, cell, ','); ++col) {
      char* end = nullptr;
      const double x = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(x)) {
        return fail(path.string() + ":" + std::to_string(line_no) + ": column " + std::to_string(col) +
                                 " ('" + cell + "') is not a finite number");
      }
      v.push_back(x);
    }
    if (v.size() != 12 && v.size() != 13) {
      return fail(path.string() + ":" + std::to_string(line_no) + ": " + std::to_string(v.size()) +
                               " columns, expected 12 or 13");
    }
    MotionSample s;
    s.time_s = v[0];
    const glm::quat q(static_cast<float>(v[4]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                      static_cast<float>(v[3]));
    const glm::vec3 g(static_cast<float>(v[8]), static_cast<float>(v[9]), static_cast<float>(v[10]));
    if (std::abs(glm::length(q) - 1.0f) > 1e-3f || std::abs(glm::length(g) - 1.0f) > 1e-3f) {
      return fail(path.string() + ":" + std::to_string(line_no) +
                               ": the orientation and the gaze must be unit length");
    }
    s.head_orientation = q;
    s.head_position_m = {float(v[5]), float(v[6]), float(v[7])};
    s.gaze_head = g;
    s.gaze_valid = v[11] != 0.0;
    s.saccade = v.size() == 13 && v[12] != 0.0;
    if (!samples.empty() && !(s.time_s > samples.back().time_s)) {
      return fail(path.string() + ":" + std::to_string(line_no) + ": time does not increase");
    }
    samples.push_back(s);
  }
  if (samples.empty()) return fail(path.string() + ": no samples");
  return ScriptedMotion(std::move(samples));
}

bool save_motion_csv(const ScriptedMotion& motion, const std::filesystem::path& path, std::string* error) {
  std::ofstream out(path);
  out.precision(9);
  out << "time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid,saccade\n";
  for (const MotionSample& s : motion.samples()) {
    const auto& q = s.head_orientation;
    out << s.time_s << ',' << q.x << ',' << q.y << ',' << q.z << ',' << q.w << ',' << s.head_position_m.x << ','
        << s.head_position_m.y << ',' << s.head_position_m.z << ',' << s.gaze_head.x << ',' << s.gaze_head.y << ','
        << s.gaze_head.z << ',' << (s.gaze_valid ? 1 : 0) << ',' << (s.saccade ? 1 : 0) << '\n';
  }
  if (!out) {
    *error = path.string() + ": cannot write the motion script";
    return false;
  }
  return true;
}

}  // namespace foveart::motion
