// Replay backend: a recorded trace at its original timing or as fast as possible.
#include <algorithm>
#include <utility>

#include "gaze_provider/trace_csv.h"
#include "threaded_provider.h"

namespace foveart::gaze {
namespace {

class ReplayBackend final : public detail::Backend {
 public:
  ReplayBackend(Trace trace, const ReplayConfig& config, std::shared_ptr<HostClock> clock)
      : trace_(std::move(trace)), config_(config), clock_(std::move(clock)) {}

  void on_start() noexcept override {
    next_ = 0;
    start_host_ns_ = clock_->now_ns();
  }

  detail::PollResult poll(GazeSample& out, std::string& reason) noexcept override {
    if (next_ >= trace_.rows.size()) {
      if (!config_.loop || trace_.rows.empty()) {
        reason = "end of trace (" + std::to_string(trace_.rows.size()) + " samples)";
        return detail::PollResult::ended;
      }
      on_start();
    }
    const GazeSample& s = trace_.rows[next_].sample;
    if (config_.original_timing) {
      const std::int64_t due =
          start_host_ns_ + (s.device_time_ns - trace_.rows.front().sample.device_time_ns);
      const std::int64_t now = clock_->now_ns();
      if (now < due) {  // at most 50 ms at a time, so that stop() stays bounded
        clock_->sleep_until_ns(std::min(due, now + 50'000'000));
        return detail::PollResult::none;
      }
    }
    out = s;
    // Original timing is a live playback: stamp arrival now, so consumers can predict to
    // their own clock. As fast as possible is an analysis pass: recorded host times stay.
    if (config_.original_timing || !trace_.rows[next_].has_host_time) out.host_time_ns = clock_->now_ns();
    ++next_;
    return detail::PollResult::sample;
  }

  GazeSourceKind kind() const noexcept override { return GazeSourceKind::replay; }
  double nominal_rate_hz() const noexcept override {
    const auto& r = trace_.rows;
    if (r.size() < 2) return 0.0;
    const double span_s = double(r.back().sample.device_time_ns - r.front().sample.device_time_ns) * 1e-9;
    return span_s > 0 ? double(r.size() - 1) / span_s : 0.0;
  }
  bool lossless() const noexcept override { return !config_.original_timing; }

 private:
  Trace trace_;
  ReplayConfig config_;
  std::shared_ptr<HostClock> clock_;
  std::size_t next_ = 0;
  std::int64_t start_host_ns_ = 0;
};

}  // namespace

std::unique_ptr<GazeProvider> create_replay_provider(const ReplayConfig& replay, const ProviderOptions& options,
                                                     std::string* error) {
  TraceError trace_error;
  auto trace = read_trace_file(replay.path, &trace_error);
  if (!trace) {
    if (error) *error = "replay: " + trace_error.to_string();
    return nullptr;
  }
  if (trace->rows.empty()) {
    if (error) *error = "replay: " + replay.path + ": the trace has a header but no samples";
    return nullptr;
  }
  return std::make_unique<detail::ThreadedProvider>(
      std::make_unique<ReplayBackend>(std::move(*trace), replay, detail::clock_of(options)), options);
}

}  // namespace foveart::gaze
