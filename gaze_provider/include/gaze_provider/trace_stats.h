// Statistics of a gaze stream or trace, as gaze-diag prints them.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "gaze_provider/filters.h"
#include "gaze_provider/trace_csv.h"

namespace foveart::gaze {

struct TraceStats {
  std::uint64_t samples = 0;
  double duration_s = 0.0;           // device time, first to last sample
  double rate_hz = 0.0;              // (samples - 1) / duration_s
  double interval_p50_ms = 0.0;      // device-time intervals
  double interval_p99_ms = 0.0;
  double jitter_ms = 0.0;            // standard deviation of the intervals
  std::uint64_t dropped = 0;         // missing frame ids (sum of gaps)
  double valid_fraction = 0.0;
  std::uint64_t eye_open = 0, eye_closed = 0, eye_not_detected = 0;
  std::uint64_t saccades = 0;        // onsets found by the filter chain
  std::uint64_t blinks = 0;          // runs of closed eyes (or of 50-500 ms invalid gaze)
  std::optional<double> latency_p50_ms;  // host - device time, when both share a clock
  std::optional<double> host_interval_p50_ms;  // host arrival intervals, when host times exist
  std::optional<double> host_interval_p99_ms;
  std::optional<double> host_jitter_ms;
  std::optional<double> accuracy_deg;    // mean angle gaze-target (valid samples with target)
  std::optional<double> precision_deg;   // RMS of successive-sample angles (valid pairs)
  std::uint64_t skipped_non_monotonic = 0;
};

// `samples` in device-time order; targets parallel to samples (may be empty).
TraceStats compute_stats(std::span<const GazeSample> samples, std::span<const std::optional<Vec3f>> targets,
                         bool host_time_known, const FilterConfig& filters = {});
TraceStats compute_stats(const Trace& trace, const FilterConfig& filters = {});

std::string stats_to_json(const TraceStats& stats, const std::string& source);
std::string stats_to_text(const TraceStats& stats, const std::string& source);

}  // namespace foveart::gaze
