// Per-sample stages of the signal chain: One Euro, I-VT saccade detection, hold.
#include "gaze_provider/filters.h"

#include <cmath>
#include <numbers>

namespace foveart::gaze {

namespace {
// Smoothing factor of a first-order low-pass at `cutoff_hz` for step `dt_s`
// (Casiez et al. 2012, eq. 4: alpha = 1 / (1 + tau / Te), tau = 1 / (2 pi fc)).
double one_euro_alpha(double cutoff_hz, double dt_s) noexcept {
  const double tau = 1.0 / (2.0 * std::numbers::pi * cutoff_hz);
  return 1.0 / (1.0 + tau / dt_s);
}
}  // namespace

double OneEuroFilter::filter(double value, std::int64_t time_ns) noexcept {
  if (!config_.enabled) return value;
  const std::int64_t dt_ns = time_ns - t_ns_;
  if (!initialized_ || dt_ns > config_.reset_gap_ns || dt_ns < 0) {
    initialized_ = true;
    x_ = value;
    dx_ = 0.0;
    t_ns_ = time_ns;
    return value;
  }
  if (dt_ns == 0) return x_;
  const double dt_s = double(dt_ns) * 1e-9;
  const double dx = (value - x_) / dt_s;
  dx_ += one_euro_alpha(config_.d_cutoff_hz, dt_s) * (dx - dx_);
  // Casiez et al. 2012, eq. 5: fc = fc_min + beta * |dx|.
  const double cutoff = config_.min_cutoff_hz + config_.beta * std::abs(dx_);
  x_ += one_euro_alpha(cutoff, dt_s) * (value - x_);
  t_ns_ = time_ns;
  return x_;
}

SaccadeDetector::Result SaccadeDetector::update(const Vec3f& direction, std::int64_t time_ns) noexcept {
  Result r;
  if (have_ > 0) {
    // Velocity over the two previous intervals when available (halves white noise).
    const int k = have_ == 2 ? 0 : 1;
    const std::int64_t dt_ns = time_ns - prev_t_[k];
    if (dt_ns > 0) r.velocity_deg_s = angle_between_deg(direction, prev_[k]) / (double(dt_ns) * 1e-9);
  }
  prev_[0] = prev_[1];
  prev_t_[0] = prev_t_[1];
  prev_[1] = direction;
  prev_t_[1] = time_ns;
  if (have_ < 2) ++have_;

  if (config_.enabled) {
    if (!in_saccade_ && r.velocity_deg_s > config_.onset_velocity_deg_s) {
      in_saccade_ = true;
      r.onset = true;
      onset_ns_ = time_ns;
    } else if (in_saccade_ && r.velocity_deg_s < config_.offset_velocity_deg_s) {
      in_saccade_ = false;
    }
  }
  r.in_saccade = in_saccade_;
  r.onset_time_ns = onset_ns_;
  return r;
}

void SaccadeDetector::reset() noexcept {
  have_ = 0;
  in_saccade_ = false;
}

void GazeHold::apply(GazeSample& sample) noexcept {
  if (sample.valid) {
    have_valid_ = true;
    last_direction_ = sample.combined_direction;
    last_valid_ns_ = sample.device_time_ns;
    holding_ = false;
    sample.hold_onset_device_ns = hold_onset_ns_;
    return;
  }
  if (config_.enabled && have_valid_ && sample.device_time_ns - last_valid_ns_ <= config_.max_hold_ns) {
    if (!holding_) hold_onset_ns_ = sample.device_time_ns;  // the run's first held sample
    holding_ = true;
    sample.combined_direction = last_direction_;
    sample.valid = true;
    sample.held = true;
    sample.hold_onset_device_ns = hold_onset_ns_;
    return;
  }
  holding_ = false;
  sample.lost = true;
  sample.hold_onset_device_ns = hold_onset_ns_;
}

FilterChain::FilterChain(const FilterConfig& config)
    : config_(config), yaw_(config.one_euro), pitch_(config.one_euro), saccade_(config.saccade),
      hold_(config.hold) {}

void FilterChain::reset() noexcept {
  yaw_.reset();
  pitch_.reset();
  saccade_.reset();
  hold_.reset();
  last_onset_ns_ = 0;
}

GazeSample FilterChain::process(const GazeSample& raw) noexcept {
  GazeSample out = raw;
  out.in_saccade = out.held = out.lost = out.extrapolated = false;
  if (out.valid && !is_finite(out.combined_direction)) out.valid = false;

  if (out.valid) {
    const Vec3f unit = normalized(out.combined_direction);
    out.combined_direction = unit;
    // I-VT on the measured direction; the smoothed one lags at saccade onset.
    if (config_.saccade.enabled) {
      const SaccadeDetector::Result s = saccade_.update(unit, out.device_time_ns);
      out.in_saccade = s.in_saccade;
      if (s.onset) last_onset_ns_ = s.onset_time_ns;
    }
    if (config_.one_euro.enabled) {
      const YawPitchDeg yp = to_yaw_pitch_deg(unit);
      out.combined_direction = from_yaw_pitch_deg(yaw_.filter(yp.yaw_deg, out.device_time_ns),
                                                  pitch_.filter(yp.pitch_deg, out.device_time_ns));
      follow_combined(out.left, out.right, unit, out.combined_direction);
    }
  } else {
    saccade_.reset();  // velocity across a gap means nothing
  }
  out.saccade_onset_device_ns = last_onset_ns_;
  hold_.apply(out);
  return out;
}

}  // namespace foveart::gaze
