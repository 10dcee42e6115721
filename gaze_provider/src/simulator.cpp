// Synthetic eye movements: fixation -> main-sequence saccade -> fixation, with
// microsaccades, blinks, white noise and a slow drift.
#include "gaze_provider/simulator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gaze_provider/gaze_math.h"

namespace foveart::gaze {

double GazeSimulator::saccade_duration_s(double amplitude_deg) noexcept {
  // Carpenter 1988: D = 2.2 ms/deg * A + 21 ms.
  return (2.2 * amplitude_deg + 21.0) * 1e-3;
}

double GazeSimulator::saccade_peak_velocity_deg_s(double amplitude_deg) noexcept {
  // Minimum-jerk profile (Flash & Hogan 1985): peak velocity = 1.875 A / D.
  return 1.875 * amplitude_deg / saccade_duration_s(amplitude_deg);
}

GazeSimulator::GazeSimulator(const SimConfig& config) : config_(config), rng_(config.seed) {
  if (!(config_.rate_hz > 0.0)) config_.rate_hz = 120.0;
  plan_fixation(0.0);
  next_micro_s_ = -std::log(1.0 - uniform()) / std::max(config_.microsaccade_rate_hz, 1e-6);
  next_blink_s_ = 0.5 - std::log(1.0 - uniform()) * config_.blink_interval_mean_s;
}

double GazeSimulator::uniform() noexcept { return double(rng_() >> 11) * 0x1.0p-53; }

double GazeSimulator::gaussian() noexcept {
  if (have_spare_) {
    have_spare_ = false;
    return spare_;
  }
  const double u1 = 1.0 - uniform();  // (0, 1]
  const double u2 = uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2.0 * std::numbers::pi * u2);
  have_spare_ = true;
  return r * std::cos(2.0 * std::numbers::pi * u2);
}

void GazeSimulator::plan_fixation(double now_s) {
  fixation_end_s_ =
      now_s + 1e-3 * (config_.fixation_min_ms + uniform() * (config_.fixation_max_ms - config_.fixation_min_ms));
}

void GazeSimulator::plan_saccade(double now_s, double amplitude_deg, bool micro) {
  // Pick a direction that keeps the target inside the field; fall back to the centre.
  double to_yaw = yaw_, to_pitch = pitch_;
  bool found = false;
  for (int attempt = 0; attempt < 16 && !found; ++attempt) {
    const double angle = 2.0 * std::numbers::pi * uniform();
    to_yaw = yaw_ + amplitude_deg * std::cos(angle);
    to_pitch = pitch_ + amplitude_deg * std::sin(angle);
    found = std::abs(to_yaw) <= config_.field_deg && std::abs(to_pitch) <= config_.field_deg;
  }
  if (!found) {
    const double len = std::hypot(yaw_, pitch_);
    const double step = std::min(amplitude_deg, len);
    to_yaw = len > 0 ? yaw_ - yaw_ / len * step : yaw_ + amplitude_deg;
    to_pitch = len > 0 ? pitch_ - pitch_ / len * step : pitch_;
  }
  from_yaw_ = yaw_;
  from_pitch_ = pitch_;
  to_yaw_ = to_yaw;
  to_pitch_ = to_pitch;
  const double amplitude = std::hypot(to_yaw - yaw_, to_pitch - pitch_);
  saccade_start_s_ = now_s;
  saccade_end_s_ = now_s + saccade_duration_s(amplitude);
  saccade_micro_ = micro;
  onset_pending_ = !micro;
}

GazeSample GazeSimulator::next(SimTruth* out_truth) {
  const double dt_s = 1.0 / config_.rate_hz;
  const double t_s = double(frame_) * dt_s;
  SimTruth truth;

  // Eye movement.
  bool in_flight = saccade_end_s_ > 0.0 && t_s < saccade_end_s_;
  if (!in_flight && saccade_end_s_ > 0.0) {  // a saccade just landed
    yaw_ = to_yaw_;
    pitch_ = to_pitch_;
    if (!saccade_micro_) plan_fixation(t_s);
    saccade_end_s_ = -1.0;
  }
  if (!in_flight) {
    if (t_s >= fixation_end_s_) {
      const double a = config_.saccade_min_deg + uniform() * (config_.saccade_max_deg - config_.saccade_min_deg);
      plan_saccade(t_s - 0.5 * dt_s, a, false);
      in_flight = true;
    } else if (config_.microsaccades && t_s >= next_micro_s_) {
      plan_saccade(t_s - 0.5 * dt_s, 0.05 + uniform() * (config_.microsaccade_max_deg - 0.05), true);
      next_micro_s_ = t_s - std::log(1.0 - uniform()) / std::max(config_.microsaccade_rate_hz, 1e-6);
      in_flight = true;
    }
  }
  if (in_flight) {
    const double tau = std::clamp((t_s - saccade_start_s_) / (saccade_end_s_ - saccade_start_s_), 0.0, 1.0);
    const double s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);  // minimum jerk
    yaw_ = from_yaw_ + (to_yaw_ - from_yaw_) * s;
    pitch_ = from_pitch_ + (to_pitch_ - from_pitch_) * s;
    truth.in_saccade = true;
    truth.amplitude_deg = std::hypot(to_yaw_ - from_yaw_, to_pitch_ - from_pitch_);
    truth.saccade_onset = onset_pending_;
    onset_pending_ = false;
  }

  // Blinks.
  if (config_.blinks && t_s >= next_blink_s_ && t_s >= blink_end_s_) {
    blink_end_s_ = t_s + 1e-3 * (config_.blink_min_ms + uniform() * (config_.blink_max_ms - config_.blink_min_ms));
    next_blink_s_ = blink_end_s_ - std::log(1.0 - uniform()) * config_.blink_interval_mean_s;
  }
  truth.in_blink = t_s < blink_end_s_;

  // Noise: Ornstein-Uhlenbeck drift plus white noise.
  const double k = dt_s / config_.noise_drift_tau_s;
  const double drift_step = config_.noise_drift_deg * std::sqrt(2.0 * k);
  drift_yaw_ += -drift_yaw_ * k + drift_step * gaussian();
  drift_pitch_ += -drift_pitch_ * k + drift_step * gaussian();
  const double m_yaw = yaw_ + drift_yaw_ + config_.noise_white_deg * gaussian();
  const double m_pitch = pitch_ + drift_pitch_ + config_.noise_white_deg * gaussian();

  truth.true_direction = from_yaw_pitch_deg(yaw_, pitch_);
  if (out_truth) *out_truth = truth;

  GazeSample g;
  g.device_time_ns = epoch_ns_ + std::llround(double(frame_) * 1e9 / config_.rate_hz);
  g.frame_id = frame_;
  g.source = GazeSourceKind::simulated;
  g.valid = !truth.in_blink;
  g.eye_state = truth.in_blink ? EyeState::closed : EyeState::open;
  g.confidence = truth.in_blink ? 0.0f : 0.95f;
  g.combined_direction = truth.in_blink ? Vec3f{0.0f, 0.0f, 1.0f} : from_yaw_pitch_deg(m_yaw, m_pitch);
  for (int eye = 0; eye < 2; ++eye) {
    EyeGaze& e = eye == 0 ? g.left : g.right;
    e.origin_m = {(eye == 0 ? -0.5f : 0.5f) * config_.ipd_m, 0.0f, 0.0f};
    e.direction = g.combined_direction;
    e.valid = g.valid;
    e.state = g.eye_state;
  }
  ++frame_;
  return g;
}

}  // namespace foveart::gaze
