// Private: the one GazeProvider implementation. A Backend reads the device; the
// ThreadedProvider runs it on a sampling thread, filters, and publishes lock-free.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "gaze_provider/backends.h"
#include "gaze_provider/gaze_provider.h"
#include "gaze_provider/seqlock.h"
#include "gaze_provider/spsc_ring.h"

namespace foveart::gaze::detail {

enum class PollResult {
  sample,        // `out` holds a new sample
  none,          // nothing new yet (timeout); call again
  disconnected,  // device/service gone; `reason` says why; call again to retry
  ended,         // no more samples, ever (replay end)
};

// Runs on the sampling thread only (poll), except open/close on the creating thread.
// poll() must return within ~100 ms so that stop() stays bounded; it must not throw.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual PollResult poll(GazeSample& out, std::string& reason) noexcept = 0;
  virtual GazeSourceKind kind() const noexcept = 0;
  virtual double nominal_rate_hz() const noexcept = 0;
  // Wait for room in the raw ring instead of dropping (replay as fast as possible).
  virtual bool lossless() const noexcept { return false; }
  // Called by start() before the thread runs (rewind, reset pacing clocks).
  virtual void on_start() noexcept {}
};

class ThreadedProvider final : public GazeProvider {
 public:
  ThreadedProvider(std::unique_ptr<Backend> backend, const ProviderOptions& options);
  ~ThreadedProvider() override;

  [[nodiscard]] bool start(std::string* error) override;
  void stop() override;
  std::optional<GazeSample> latest() const override;
  std::optional<GazeSample> sample_at(std::int64_t target_host_ns) const override;
  ProviderStatus status() const override;
  std::size_t read_raw(std::span<GazeSample> out) override;
  GazeSourceKind source() const override { return backend_->kind(); }
  double nominal_rate_hz() const override { return backend_->nominal_rate_hz(); }

 private:
  void run() noexcept;
  void set_state(ProviderState state, const std::string& reason) noexcept;

  std::unique_ptr<Backend> backend_;
  std::shared_ptr<HostClock> clock_;
  FilterConfig filters_;
  SpscRing<GazeSample> raw_;
  SeqlockHistory<GazeSample, 32> history_;
  SeqlockCell<ProviderStatus> status_;
  ProviderStatus producer_status_{};  // sampling thread's copy (or controller's when stopped)
  std::atomic<bool> running_{false};
  std::thread thread_;
};

std::int64_t steady_now_ns() noexcept;

// options.clock, else the steady clock.
inline std::shared_ptr<HostClock> clock_of(const ProviderOptions& options) {
  return options.clock ? options.clock : steady_host_clock();
}

}  // namespace foveart::gaze::detail
