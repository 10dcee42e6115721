// Simulated backend: GazeSimulator paced at its rate on an absolute schedule, so
// a late wake-up never accumulates drift. Its device clock is the host clock.
#include <algorithm>
#include <cmath>
#include <utility>

#include "threaded_provider.h"

namespace foveart::gaze {
namespace {

class SimBackend final : public detail::Backend {
 public:
  SimBackend(const SimConfig& config, std::shared_ptr<HostClock> clock)
      : config_(config), sim_(config), clock_(std::move(clock)) {}

  void on_start() noexcept override {
    sim_ = GazeSimulator(config_);
    start_ns_ = clock_->now_ns();
    sim_.set_device_epoch_ns(start_ns_);
  }

  // Sleeps at most 50 ms at a time (stop() stays bounded), and only hands out a
  // sample once it is due.
  detail::PollResult poll(GazeSample& out, std::string&) noexcept override {
    const std::int64_t due_ns = start_ns_ + std::llround(double(sim_.frames()) * 1e9 / config_.rate_hz);
    const std::int64_t now_ns = clock_->now_ns();
    if (now_ns < due_ns) {
      clock_->sleep_until_ns(std::min(due_ns, now_ns + 50'000'000));
      return detail::PollResult::none;
    }
    out = sim_.next();
    out.host_time_ns = clock_->now_ns();
    return detail::PollResult::sample;
  }

  GazeSourceKind kind() const noexcept override { return GazeSourceKind::simulated; }
  double nominal_rate_hz() const noexcept override { return config_.rate_hz; }

 private:
  SimConfig config_;
  GazeSimulator sim_;
  std::shared_ptr<HostClock> clock_;
  std::int64_t start_ns_ = 0;
};

}  // namespace

std::unique_ptr<GazeProvider> create_sim_provider(const SimConfig& sim, const ProviderOptions& options,
                                                  std::string* error) {
  if (!(sim.rate_hz > 0.0 && sim.rate_hz <= 10000.0)) {
    if (error) *error = "sim: rate_hz must be in (0, 10000]";
    return nullptr;
  }
  return std::make_unique<detail::ThreadedProvider>(std::make_unique<SimBackend>(sim, detail::clock_of(options)),
                                                    options);
}

}  // namespace foveart::gaze
