// Statistics of a gaze stream or trace (gaze-diag stream/report).
#include "gaze_provider/trace_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace foveart::gaze {

namespace {
// Nearest rank, p in percent; 0 for none. The same definition as foveation/percentile.hpp,
// which gaze_provider does not include: it depends on no other FoveaRT module (docs/design.md).
double percentile(std::vector<double> v, double p_percent) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p_percent / 100.0 * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

std::string num(double v, int precision = 4) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", precision, v);
  return buf;
}

// Median, 99th percentile and standard deviation of intervals (ms).
struct IntervalStats {
  double p50_ms, p99_ms, sd_ms;
};

IntervalStats interval_stats(const std::vector<double>& ms) {
  double sum = 0, sum2 = 0;
  for (double dt : ms) {
    sum += dt;
    sum2 += dt * dt;
  }
  const double n = double(ms.size());
  return {percentile(ms, 50), percentile(ms, 99), std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)))};
}

// Validity, eye states, dropped frames, device-time intervals and latency.
void add_device_timing(std::span<const GazeSample> s, bool host_time_known, TraceStats& st) {
  std::vector<double> intervals_ms, latency_ms;
  std::uint64_t valid = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].valid) ++valid;
    switch (s[i].eye_state) {
      case EyeState::open: ++st.eye_open; break;
      case EyeState::closed: ++st.eye_closed; break;
      case EyeState::not_detected: ++st.eye_not_detected; break;
    }
    if (host_time_known) latency_ms.push_back(double(s[i].host_time_ns - s[i].device_time_ns) * 1e-6);
    if (i == 0) continue;
    intervals_ms.push_back(double(s[i].device_time_ns - s[i - 1].device_time_ns) * 1e-6);
    if (s[i].frame_id > s[i - 1].frame_id + 1) st.dropped += s[i].frame_id - s[i - 1].frame_id - 1;
  }
  st.valid_fraction = double(valid) / double(s.size());
  if (!intervals_ms.empty()) {
    const IntervalStats d = interval_stats(intervals_ms);
    st.interval_p50_ms = d.p50_ms;
    st.interval_p99_ms = d.p99_ms;
    st.jitter_ms = d.sd_ms;
  }
  // Latency only when host and device share a clock (plausible 0..1 s offsets).
  if (!latency_ms.empty()) {
    const double p50 = percentile(latency_ms, 50);
    if (p50 >= 0.0 && p50 < 1000.0) st.latency_p50_ms = p50;
  }
}

// Host arrival intervals (at least two samples).
void add_host_intervals(std::span<const GazeSample> s, TraceStats& st) {
  std::vector<double> host_ms;
  for (std::size_t i = 1; i < s.size(); ++i)
    host_ms.push_back(double(s[i].host_time_ns - s[i - 1].host_time_ns) * 1e-6);
  const IntervalStats h = interval_stats(host_ms);
  st.host_interval_p50_ms = h.p50_ms;
  st.host_interval_p99_ms = h.p99_ms;
  st.host_jitter_ms = h.sd_ms;
}

// Saccades: onsets found by the filter chain (hold/prediction do not matter here).
std::uint64_t count_saccades(std::span<const GazeSample> s, const FilterConfig& filters) {
  FilterChain chain(filters);
  std::uint64_t saccades = 0;
  std::int64_t last_onset = 0;
  for (const GazeSample& g : s) {
    const GazeSample f = chain.process(g);
    if (f.saccade_onset_device_ns != 0 && f.saccade_onset_device_ns != last_onset) {
      ++saccades;
      last_onset = f.saccade_onset_device_ns;
    }
  }
  return saccades;
}

// Blinks: runs of closed eyes; without eye state (none closed), runs of 50-500 ms invalid gaze.
std::uint64_t count_blinks(std::span<const GazeSample> s, bool any_closed) {
  std::uint64_t blinks = 0;
  std::size_t run_start = 0;
  bool in_run = false;
  for (std::size_t i = 0; i <= s.size(); ++i) {
    const bool blinking = i < s.size() && (any_closed ? s[i].eye_state == EyeState::closed : !s[i].valid);
    if (blinking && !in_run) {
      in_run = true;
      run_start = i;
    } else if (!blinking && in_run) {
      in_run = false;
      const double ms = double(s[i - 1].device_time_ns - s[run_start].device_time_ns) * 1e-6;
      if (any_closed || (ms >= 50.0 && ms <= 500.0)) ++blinks;
    }
  }
  return blinks;
}

// Accuracy (mean angle to the target) and precision (RMS sample to sample), in degrees.
void add_accuracy(std::span<const GazeSample> s, std::span<const std::optional<Vec3f>> targets, TraceStats& st) {
  double acc_sum = 0;
  std::uint64_t acc_n = 0;
  for (std::size_t i = 0; i < s.size() && i < targets.size(); ++i) {
    if (s[i].valid && targets[i]) {
      acc_sum += angle_between_deg(s[i].combined_direction, *targets[i]);
      ++acc_n;
    }
  }
  if (acc_n == 0) return;
  st.accuracy_deg = acc_sum / double(acc_n);
  double p_sum2 = 0;
  std::uint64_t p_n = 0;
  for (std::size_t i = 1; i < s.size(); ++i) {
    if (s[i].valid && s[i - 1].valid) {
      const double a = angle_between_deg(s[i].combined_direction, s[i - 1].combined_direction);
      p_sum2 += a * a;
      ++p_n;
    }
  }
  if (p_n > 0) st.precision_deg = std::sqrt(p_sum2 / double(p_n));
}
}  // namespace

TraceStats compute_stats(std::span<const GazeSample> s, std::span<const std::optional<Vec3f>> targets,
                         bool host_time_known, const FilterConfig& filters) {
  TraceStats st;
  st.samples = s.size();
  if (s.empty()) return st;
  st.duration_s = double(s.back().device_time_ns - s.front().device_time_ns) * 1e-9;
  st.rate_hz = st.duration_s > 0 ? double(s.size() - 1) / st.duration_s : 0.0;
  add_device_timing(s, host_time_known, st);
  if (host_time_known && s.size() > 1) add_host_intervals(s, st);
  st.saccades = count_saccades(s, filters);
  st.blinks = count_blinks(s, st.eye_closed > 0);
  add_accuracy(s, targets, st);
  return st;
}

TraceStats compute_stats(const Trace& trace, const FilterConfig& filters) {
  std::vector<GazeSample> samples;
  std::vector<std::optional<Vec3f>> targets;
  samples.reserve(trace.rows.size());
  for (const TraceRow& r : trace.rows) {
    samples.push_back(r.sample);
    targets.push_back(r.target);
  }
  TraceStats st = compute_stats(samples, trace.has_targets ? std::span<const std::optional<Vec3f>>(targets)
                                                           : std::span<const std::optional<Vec3f>>(),
                                trace.has_host_time, filters);
  st.skipped_non_monotonic = trace.skipped_non_monotonic;
  return st;
}

std::string stats_to_json(const TraceStats& st, const std::string& source) {
  std::string esc;
  for (char c : source) {
    if (c == '"' || c == '\\') esc += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) esc += c;
  }
  std::string j = "{\n";
  auto field = [&j](const char* k, const std::string& v) { j += std::string("  \"") + k + "\": " + v + ",\n"; };
  field("source", "\"" + esc + "\"");
  field("samples", std::to_string(st.samples));
  field("duration_s", num(st.duration_s));
  field("rate_hz", num(st.rate_hz));
  field("interval_p50_ms", num(st.interval_p50_ms));
  field("interval_p99_ms", num(st.interval_p99_ms));
  field("jitter_ms", num(st.jitter_ms));
  field("dropped", std::to_string(st.dropped));
  field("valid_fraction", num(st.valid_fraction));
  field("eye_open", std::to_string(st.eye_open));
  field("eye_closed", std::to_string(st.eye_closed));
  field("eye_not_detected", std::to_string(st.eye_not_detected));
  field("saccades", std::to_string(st.saccades));
  field("blinks", std::to_string(st.blinks));
  field("skipped_non_monotonic", std::to_string(st.skipped_non_monotonic));
  if (st.latency_p50_ms) field("latency_p50_ms", num(*st.latency_p50_ms));
  if (st.host_interval_p50_ms) field("host_interval_p50_ms", num(*st.host_interval_p50_ms));
  if (st.host_interval_p99_ms) field("host_interval_p99_ms", num(*st.host_interval_p99_ms));
  if (st.host_jitter_ms) field("host_jitter_ms", num(*st.host_jitter_ms));
  if (st.accuracy_deg) field("accuracy_deg", num(*st.accuracy_deg));
  if (st.precision_deg) field("precision_deg", num(*st.precision_deg));
  j.resize(j.size() - 2);  // drop the last ",\n"
  j += "\n}\n";
  return j;
}

std::string stats_to_text(const TraceStats& st, const std::string& source) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "source          %s\n"
                "samples         %llu over %.3f s\n"
                "rate            %.3f Hz\n"
                "interval        p50 %.3f ms, p99 %.3f ms, jitter (sd) %.3f ms\n"
                "dropped frames  %llu\n"
                "valid           %.1f %%\n"
                "eye state       open %llu, closed %llu, not detected %llu\n"
                "saccades        %llu\n"
                "blinks          %llu\n",
                source.c_str(), static_cast<unsigned long long>(st.samples), st.duration_s, st.rate_hz,
                st.interval_p50_ms, st.interval_p99_ms, st.jitter_ms, static_cast<unsigned long long>(st.dropped),
                100.0 * st.valid_fraction, static_cast<unsigned long long>(st.eye_open),
                static_cast<unsigned long long>(st.eye_closed), static_cast<unsigned long long>(st.eye_not_detected),
                static_cast<unsigned long long>(st.saccades), static_cast<unsigned long long>(st.blinks));
  std::string s = buf;
  if (st.skipped_non_monotonic) s += "skipped rows    " + std::to_string(st.skipped_non_monotonic) + " (non-monotonic time)\n";
  if (st.latency_p50_ms) s += "latency         p50 " + num(*st.latency_p50_ms, 3) + " ms (device -> host)\n";
  else s += "latency         unknown (device clock differs from host clock)\n";
  if (st.host_interval_p50_ms)
    s += "host arrival    p50 " + num(*st.host_interval_p50_ms, 3) + " ms, p99 " + num(*st.host_interval_p99_ms, 3) +
         " ms, jitter (sd) " + num(*st.host_jitter_ms, 3) + " ms\n";
  if (st.accuracy_deg) s += "accuracy        " + num(*st.accuracy_deg, 3) + " deg (mean offset to target)\n";
  if (st.precision_deg) s += "precision       " + num(*st.precision_deg, 3) + " deg (RMS sample-to-sample)\n";
  return s;
}

}  // namespace foveart::gaze
