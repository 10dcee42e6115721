// The runtime's time base. XrTime is int64 nanoseconds of this clock.
//   real:    CLOCK_MONOTONIC (so XR_KHR_convert_timespec_time is the identity)
//   virtual: starts at env::kVirtualEpochNs and only moves when someone sleeps. It is
//            anchored to CLOCK_MONOTONIC each time it moves: between two moves an XrTime
//            converts to and from a timespec by one fixed offset (exact round trips), and
//            "now" converts to CLOCK_MONOTONIC at the last move.
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
  // XR_KHR_convert_timespec_time: this clock's time <-> CLOCK_MONOTONIC nanoseconds.
  int64_t to_monotonic_ns(int64_t time_ns) const { return time_ns + monotonic_offset_ns_; }
  int64_t from_monotonic_ns(int64_t monotonic_ns) const { return monotonic_ns - monotonic_offset_ns_; }

 private:
  bool virtual_;
  int64_t virtual_now_ns_;
  int64_t monotonic_offset_ns_ = 0;  // CLOCK_MONOTONIC minus this clock (virtual: at the last move)
};

int64_t monotonic_now_ns();

}  // namespace foveart::sim
