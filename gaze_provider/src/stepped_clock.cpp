#include "gaze_provider/stepped_clock.h"

#include <algorithm>
#include <limits>
#include <thread>

namespace foveart::gaze {

std::int64_t SteppedClock::now_ns() noexcept {
  std::lock_guard lock(mutex_);
  return now_;
}

void SteppedClock::sleep_until_ns(std::int64_t t_ns) noexcept {
  std::unique_lock lock(mutex_);
  longest_sleep_ns_ = std::max(longest_sleep_ns_, t_ns - now_);
  const auto it = deadlines_.insert(t_ns);
  changed_.notify_all();
  changed_.wait(lock, [&] { return now_ >= t_ns || released_; });
  deadlines_.erase(it);
  changed_.notify_all();
}

void SteppedClock::advance_to(std::int64_t t_ns) {
  std::lock_guard lock(mutex_);
  now_ = std::max(now_, t_ns);
  changed_.notify_all();
}

bool SteppedClock::settle(const std::function<bool()>& done) {
  std::unique_lock lock(mutex_);
  const auto give_up = std::chrono::steady_clock::now() + kGuard;
  for (;;) {
    if (!deadlines_.empty() && *deadlines_.rbegin() > now_) return true;
    if (done) {
      lock.unlock();
      const bool finished = done();
      lock.lock();
      if (finished) return true;
    }
    if (std::chrono::steady_clock::now() > give_up) return false;
    // A sleeper arriving notifies; `done` may change without a notification.
    changed_.wait_for(lock, std::chrono::milliseconds(1));
  }
}

bool SteppedClock::run_until(std::int64_t t_ns, const std::function<bool()>& done) {
  for (;;) {
    if (!settle(done)) return false;
    if (done && done()) return true;
    std::lock_guard lock(mutex_);
    std::int64_t next = std::numeric_limits<std::int64_t>::max();
    for (std::int64_t d : deadlines_)
      if (d > now_) next = std::min(next, d);
    if (next > t_ns) {
      now_ = std::max(now_, t_ns);
      changed_.notify_all();
      break;
    }
    now_ = next;
    changed_.notify_all();
  }
  return settle(done);
}

bool SteppedClock::eventually(const std::function<bool()>& condition) {
  const auto give_up = std::chrono::steady_clock::now() + kGuard;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::yield();
  }
  return true;
}

void SteppedClock::release() {
  std::lock_guard lock(mutex_);
  released_ = true;
  changed_.notify_all();
}

std::int64_t SteppedClock::longest_sleep_ns() {
  std::lock_guard lock(mutex_);
  return longest_sleep_ns_;
}

}  // namespace foveart::gaze
