// Synthetic eye: fixations, main-sequence saccades, microsaccades, blinks and
// measurement noise, deterministic for a seed (same seed, same build -> same samples;
// the generator uses its own distributions, not <random>'s, so it is also stable
// across standard libraries).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "gaze_provider/gaze_sample.h"

namespace foveart::gaze {

struct SimConfig {
  std::uint64_t seed = 1;
  double rate_hz = 120.0;
  double field_deg = 20.0;                 // fixation targets within +-field_deg (yaw and pitch)
  double fixation_min_ms = 180.0;
  double fixation_max_ms = 450.0;
  double saccade_min_deg = 2.0;
  double saccade_max_deg = 18.0;
  bool microsaccades = true;
  double microsaccade_rate_hz = 1.2;       // during fixations
  double microsaccade_max_deg = 0.5;
  bool blinks = true;
  double blink_interval_mean_s = 4.0;
  double blink_min_ms = 100.0;
  double blink_max_ms = 200.0;
  double noise_white_deg = 0.15;           // per-axis Gaussian noise per sample
  double noise_drift_deg = 0.9;            // slow offset (Ornstein-Uhlenbeck, tau 1 s)
  double noise_drift_tau_s = 1.0;
  float ipd_m = 0.064f;
};

// Ground truth for one generated sample.
struct SimTruth {
  Vec3f true_direction{};
  bool in_saccade = false;     // macro- or microsaccade in flight
  bool saccade_onset = false;  // first sample of a saccade (amplitude >= saccade_min_deg)
  bool in_blink = false;
  double amplitude_deg = 0.0;  // of the saccade in flight
};

class GazeSimulator {
 public:
  explicit GazeSimulator(const SimConfig& config = {});

  // Sample number `frame_id_` at device time frame_id * 1e9 / rate_hz (+ epoch).
  GazeSample next(SimTruth* out_truth = nullptr);
  std::uint64_t frames() const noexcept { return frame_; }
  const SimConfig& config() const noexcept { return config_; }
  void set_device_epoch_ns(std::int64_t epoch_ns) noexcept { epoch_ns_ = epoch_ns; }

  // Main sequence used by the generator (Carpenter 1988: D = 2.2 ms/deg * A + 21 ms;
  // minimum-jerk profile, Flash & Hogan 1985, peak velocity = 1.875 A / D).
  static double saccade_duration_s(double amplitude_deg) noexcept;
  static double saccade_peak_velocity_deg_s(double amplitude_deg) noexcept;

 private:
  double uniform() noexcept;   // [0, 1)
  double gaussian() noexcept;  // N(0, 1), Box-Muller
  void plan_fixation(double now_s);
  void plan_saccade(double now_s, double amplitude_deg, bool micro);

  SimConfig config_;
  std::mt19937_64 rng_;
  std::uint64_t frame_ = 0;
  std::int64_t epoch_ns_ = 0;
  // eye state in yaw/pitch degrees
  double yaw_ = 0.0, pitch_ = 0.0;
  double from_yaw_ = 0.0, from_pitch_ = 0.0, to_yaw_ = 0.0, to_pitch_ = 0.0;
  double saccade_start_s_ = -1.0, saccade_end_s_ = -1.0;
  bool saccade_micro_ = false;
  bool onset_pending_ = false;
  double fixation_end_s_ = 0.0;
  double next_micro_s_ = 0.0;
  double next_blink_s_ = 0.0, blink_end_s_ = -1.0;
  double drift_yaw_ = 0.0, drift_pitch_ = 0.0;
  bool have_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace foveart::gaze
