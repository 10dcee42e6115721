// The gaze signal chain: One Euro smoothing -> saccade detection -> blink/dropout
// hold, run per sample on the producer thread, and prediction to a target host
// time, run on the reader's thread. Each stage is optional (FilterConfig) and
// usable on its own (the tests drive them with synthetic signals).
//
// Threads: every class here is single-threaded; the provider owns one FilterChain
// on its sampling thread. predict_gaze() is a pure function.
// Units: times in ns (device clock unless named host), angles in degrees.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "gaze_provider/gaze_math.h"
#include "gaze_provider/gaze_sample.h"

namespace foveart::gaze {

struct OneEuroConfig {
  bool enabled = true;
  double min_cutoff_hz = 1.0;  // smoothing at rest (lower: smoother, more lag)
  double beta = 0.2;           // cutoff increase per deg/s of speed (higher: less lag, more jitter)
  double d_cutoff_hz = 1.0;    // cutoff of the speed estimate
  std::int64_t reset_gap_ns = 100'000'000;  // restart after a gap (blink) this long
};

struct SaccadeConfig {
  bool enabled = true;
  double onset_velocity_deg_s = 75.0;  // I-VT threshold, issue range ~30-100 deg/s
  double offset_velocity_deg_s = 50.0; // hysteresis: saccade ends below this
};

struct HoldConfig {
  bool enabled = true;
  std::int64_t max_hold_ns = 200'000'000;  // reuse last valid gaze this long, then "lost"
};

struct PredictionConfig {
  bool enabled = true;
  std::int64_t max_horizon_ns = 60'000'000;  // never extrapolate further than this
  std::size_t window = 4;                     // samples in the velocity fit
  double max_speed_deg_s = 60.0;              // pursuit limit; faster motion is not extrapolated
};

struct FilterConfig {
  OneEuroConfig one_euro{};
  SaccadeConfig saccade{};
  HoldConfig hold{};
  PredictionConfig prediction{};
};

// One Euro filter on a scalar (Casiez, Roussel, Vogel, CHI 2012).
class OneEuroFilter {
 public:
  explicit OneEuroFilter(const OneEuroConfig& config = {}) : config_(config) {}
  double filter(double value, std::int64_t time_ns) noexcept;
  void reset() noexcept { initialized_ = false; }

 private:
  OneEuroConfig config_;
  bool initialized_ = false;
  double x_ = 0.0;
  double dx_ = 0.0;
  std::int64_t t_ns_ = 0;
};

// Velocity-threshold (I-VT) saccade detector with hysteresis
// (Salvucci & Goldberg 2000). Velocity spans two sample intervals to halve noise.
class SaccadeDetector {
 public:
  explicit SaccadeDetector(const SaccadeConfig& config = {}) : config_(config) {}
  struct Result {
    bool in_saccade = false;
    bool onset = false;               // this sample starts a saccade
    double velocity_deg_s = 0.0;
    std::int64_t onset_time_ns = 0;   // of the current or last saccade, 0 if none
  };
  // Feed valid samples only, in device-time order.
  Result update(const Vec3f& direction, std::int64_t time_ns) noexcept;
  void reset() noexcept;

 private:
  SaccadeConfig config_;
  Vec3f prev_[2]{};
  std::int64_t prev_t_[2]{};
  int have_ = 0;
  bool in_saccade_ = false;
  std::int64_t onset_ns_ = 0;
};

// Blink/dropout hold: invalid samples take the last valid direction for at most
// max_hold_ns (device time), after which they are marked lost. Every sample carries
// the device time of the current or last hold's first sample (hold_onset_device_ns).
class GazeHold {
 public:
  explicit GazeHold(const HoldConfig& config = {}) : config_(config) {}
  void apply(GazeSample& sample) noexcept;  // edits valid/held/lost/combined_direction
  void reset() noexcept { have_valid_ = holding_ = false; }

 private:
  HoldConfig config_;
  bool have_valid_ = false;
  bool holding_ = false;
  Vec3f last_direction_{};
  std::int64_t last_valid_ns_ = 0;
  std::int64_t hold_onset_ns_ = 0;
};

// The per-sample chain run by the sampling thread.
class FilterChain {
 public:
  explicit FilterChain(const FilterConfig& config = {});
  GazeSample process(const GazeSample& raw) noexcept;  // returns the filtered sample
  void reset() noexcept;
  const FilterConfig& config() const noexcept { return config_; }

 private:
  FilterConfig config_;
  OneEuroFilter yaw_;
  OneEuroFilter pitch_;
  SaccadeDetector saccade_;
  GazeHold hold_;
  std::int64_t last_valid_ns_ = 0;
  bool have_valid_ = false;
  std::int64_t last_onset_ns_ = 0;
};

// Gaze at `target_host_ns` from filtered samples, newest first.
//  - target at or before the newest sample: interpolated between bracketing samples;
//  - after it: linear extrapolation (velocity from device time, horizon from host
//    time, capped at max_horizon_ns), but never when the newest sample is in a
//    saccade, or a saccade onset lies inside the fitting window, or the speed exceeds
//    max_speed_deg_s: then the newest measured direction is returned unchanged;
//  - newest sample lost/invalid, or older than the hold time: returned as is (invalid).
// Returns false when `newest_first` is empty.
bool predict_gaze(std::span<const GazeSample> newest_first, std::int64_t target_host_ns,
                  const FilterConfig& config, GazeSample& out) noexcept;

}  // namespace foveart::gaze
