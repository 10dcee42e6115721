// The host clock a provider paces and stamps its samples by (GazeSample::host_time_ns,
// sample_at's target). std::chrono::steady_clock unless ProviderOptions::clock names
// another: tests drive a virtual one, so that no pass/fail check waits on real time.
#pragma once

#include <cstdint>
#include <memory>

namespace foveart::gaze {

class HostClock {
 public:
  virtual ~HostClock() = default;
  // int64 nanoseconds, monotonic.
  virtual std::int64_t now_ns() noexcept = 0;
  // Returns once now_ns() >= t_ns, or earlier (a virtual clock stopping): callers
  // re-check the time and never act as though t_ns had come.
  virtual void sleep_until_ns(std::int64_t t_ns) noexcept = 0;
};

// std::chrono::steady_clock, shared by every provider that names no clock.
std::shared_ptr<HostClock> steady_host_clock();

}  // namespace foveart::gaze
