// Simulated backend: GazeSimulator paced at its rate on an absolute schedule, so
// a late wake-up never accumulates drift. Its device clock is the host steady clock.
#include <chrono>
#include <thread>

#include "threaded_provider.h"

namespace foveart::gaze {
namespace {

class SimBackend final : public detail::Backend {
 public:
  explicit SimBackend(const SimConfig& config) : config_(config), sim_(config) {}

  void on_start() noexcept override {
    sim_ = GazeSimulator(config_);
    start_ns_ = detail::steady_now_ns();
    sim_.set_device_epoch_ns(start_ns_);
  }

  detail::PollResult poll(GazeSample& out, std::string&) noexcept override {
    const std::int64_t due_ns = start_ns_ + std::llround(double(sim_.frames()) * 1e9 / config_.rate_hz);
    const std::int64_t wait_ns = due_ns - detail::steady_now_ns();
    if (wait_ns > 50'000'000) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      return detail::PollResult::none;
    }
    if (wait_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait_ns));
    out = sim_.next();
    out.host_time_ns = detail::steady_now_ns();
    return detail::PollResult::sample;
  }

  GazeSourceKind kind() const noexcept override { return GazeSourceKind::simulated; }
  double nominal_rate_hz() const noexcept override { return config_.rate_hz; }

 private:
  SimConfig config_;
  GazeSimulator sim_;
  std::int64_t start_ns_ = 0;
};

}  // namespace

std::unique_ptr<GazeProvider> create_sim_provider(const SimConfig& sim, const ProviderOptions& options,
                                                  std::string* out_error) {
  if (!(sim.rate_hz > 0.0 && sim.rate_hz <= 10000.0)) {
    if (out_error) *out_error = "sim: rate_hz must be in (0, 10000]";
    return nullptr;
  }
  return std::make_unique<detail::ThreadedProvider>(std::make_unique<SimBackend>(sim), options);
}

}  // namespace foveart::gaze
