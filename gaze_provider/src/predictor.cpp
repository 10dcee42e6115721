// Gaze at a target host time: interpolation inside the history, bounded linear
// extrapolation beyond it, never across a saccade onset.
#include <algorithm>
#include <cmath>

#include "gaze_provider/filters.h"

namespace foveart::gaze {

namespace {
Vec3f lerp_direction(const Vec3f& a, const Vec3f& b, double t) noexcept {
  auto mix = [t](float u, float v) { return float(double(u) + (double(v) - double(u)) * t); };
  return normalized({mix(a.x, b.x), mix(a.y, b.y), mix(a.z, b.z)});
}
}  // namespace

bool predict_gaze(std::span<const GazeSample> s, std::int64_t target_host_ns, const FilterConfig& config,
                  GazeSample& out) noexcept {
  if (s.empty()) return false;
  const GazeSample& newest = s[0];
  out = newest;
  out.extrapolated = false;
  if (!newest.valid) return true;

  // Stale: nothing arrived for longer than the hold time plus the prediction horizon.
  const std::int64_t age_ns = target_host_ns - newest.host_time_ns;
  const std::int64_t stale_ns =
      (config.hold.enabled ? config.hold.max_hold_ns : 0) + config.prediction.max_horizon_ns;
  if (age_ns > stale_ns) {
    out.valid = false;
    out.lost = true;
    return true;
  }

  // Inside the history: interpolate between the bracketing samples.
  if (age_ns <= 0) {
    for (std::size_t i = 1; i < s.size(); ++i) {
      const GazeSample& older = s[i];
      const GazeSample& newer = s[i - 1];
      if (older.host_time_ns <= target_host_ns) {
        if (!older.valid) {
          out = newer;
          return true;
        }
        const std::int64_t span = newer.host_time_ns - older.host_time_ns;
        const double t = span > 0 ? double(target_host_ns - older.host_time_ns) / double(span) : 1.0;
        out = t < 0.5 ? older : newer;
        const Vec3f picked = out.combined_direction;
        out.combined_direction = lerp_direction(older.combined_direction, newer.combined_direction, t);
        follow_combined(out.left, out.right, picked, out.combined_direction);
        return true;
      }
    }
    out = s.back();  // older than everything we hold
    return true;
  }

  const PredictionConfig& p = config.prediction;
  if (!p.enabled || newest.in_saccade || newest.held) return true;

  // Fit window: consecutive measured samples since the last saccade onset.
  std::size_t n = 0;
  double st = 0, sy = 0, sp = 0, stt = 0, sty = 0, stp = 0;
  const std::int64_t t0 = newest.device_time_ns;
  for (const GazeSample& g : s) {
    if (n >= std::max<std::size_t>(p.window, 2)) break;
    if (!g.valid || g.held || g.in_saccade || g.saccade_onset_device_ns != newest.saccade_onset_device_ns)
      break;
    const double t = double(g.device_time_ns - t0) * 1e-9;
    const YawPitchDeg yp = to_yaw_pitch_deg(g.combined_direction);
    st += t;
    sy += yp.yaw_deg;
    sp += yp.pitch_deg;
    stt += t * t;
    sty += t * yp.yaw_deg;
    stp += t * yp.pitch_deg;
    ++n;
  }
  if (n < 2) return true;
  const double dn = double(n);
  const double denom = dn * stt - st * st;
  if (!(std::abs(denom) > 1e-18)) return true;
  // Least-squares line per axis: value(t) = a + b t.
  const double b_yaw = (dn * sty - st * sy) / denom;
  const double b_pitch = (dn * stp - st * sp) / denom;
  const double a_yaw = (sy - b_yaw * st) / dn;
  const double a_pitch = (sp - b_pitch * st) / dn;
  if (std::hypot(b_yaw, b_pitch) > p.max_speed_deg_s) return true;

  const double horizon_s = double(std::min(age_ns, p.max_horizon_ns)) * 1e-9;
  out.combined_direction = from_yaw_pitch_deg(a_yaw + b_yaw * horizon_s, a_pitch + b_pitch * horizon_s);
  follow_combined(out.left, out.right, newest.combined_direction, out.combined_direction);
  out.extrapolated = true;
  return true;
}

}  // namespace foveart::gaze
