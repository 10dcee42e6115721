#include "sim_clock.h"

#include <cerrno>
#include <ctime>

#include "sim_runtime/sim_env.h"

namespace foveart::sim {

int64_t monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

SimClock::SimClock(bool is_virtual)
    : virtual_(is_virtual),
      virtual_now_ns_(env::kVirtualEpochNs),
      monotonic_offset_ns_(is_virtual ? monotonic_now_ns() - env::kVirtualEpochNs : 0) {}

int64_t SimClock::now_ns() const {
  return virtual_ ? virtual_now_ns_ : monotonic_now_ns();
}

void SimClock::sleep_until_ns(int64_t t_ns) {
  if (virtual_) {
    if (t_ns > virtual_now_ns_) virtual_now_ns_ = t_ns;
    monotonic_offset_ns_ = monotonic_now_ns() - virtual_now_ns_;  // re-anchored as it moves
    return;
  }
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(t_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace foveart::sim
