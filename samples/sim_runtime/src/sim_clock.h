// The runtime's time base. XrTime is int64 nanoseconds of this clock.
//   real:    CLOCK_MONOTONIC (so XR_KHR_convert_timespec_time is the identity)
//   virtual: starts at env::kVirtualEpochNs and only moves when someone sleeps
#pragma once

#include <cstdint>

namespace foveart::sim {

class SimClock {
 public:
  explicit SimClock(bool is_virtual);
  int64_t now_ns() const;
  // Real: sleeps until t_ns (no-op when past). Virtual: jumps to t_ns if later.
  void sleep_until_ns(int64_t t_ns);
  bool is_virtual() const { return virtual_; }

 private:
  bool virtual_;
  int64_t virtual_now_ns_;
};

int64_t monotonic_now_ns();

}  // namespace foveart::sim
