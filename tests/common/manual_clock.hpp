// A virtual host clock for the gaze provider's tests (gaze_provider/host_clock.h):
// time moves only when the test moves it, and a provider's sampling thread sleeps
// on it until then. Pass/fail checks then follow virtual time, never the machine's
// scheduler. Real time appears only in guards: a wait that gives up after
// kGuard reports failure; it cannot make a test pass.
#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <set>
#include <thread>

#include "gaze_provider/host_clock.h"

namespace foveart::test {

class ManualClock final : public gaze::HostClock {
 public:
  static constexpr std::chrono::seconds kGuard{20};

  explicit ManualClock(std::int64_t start_ns = 1'000'000'000) : now_(start_ns) {}

  std::int64_t now_ns() noexcept override {
    std::lock_guard lock(mutex_);
    return now_;
  }

  void sleep_until_ns(std::int64_t t_ns) noexcept override {
    std::unique_lock lock(mutex_);
    longest_sleep_ns_ = std::max(longest_sleep_ns_, t_ns - now_);
    const auto it = deadlines_.insert(t_ns);
    changed_.notify_all();
    changed_.wait(lock, [&] { return now_ >= t_ns || released_; });
    deadlines_.erase(it);
    changed_.notify_all();
  }

  // Moves time to t_ns (never back) and wakes the sleepers it reaches.
  void advance_to(std::int64_t t_ns) {
    std::lock_guard lock(mutex_);
    now_ = std::max(now_, t_ns);
    changed_.notify_all();
  }

  // Waits until `done` holds or some thread sleeps past now: whatever was due by
  // now has been done. False when neither happens within kGuard of real time.
  bool settle(const std::function<bool()>& done = {}) {
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

  // Steps time from sleeper deadline to sleeper deadline up to t_ns, letting the
  // sleepers act at each, as a perfectly punctual scheduler would; then settles.
  // Stops early, time where it is, once `done` holds (a provider that ended and
  // sleeps no more). False when a step does not settle (see settle).
  bool run_until(std::int64_t t_ns, const std::function<bool()>& done = {}) {
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

  // Waits (real time, at most kGuard) until `condition` holds, for what other
  // threads do without sleeping on this clock. False when it never does.
  static bool eventually(const std::function<bool()>& condition) {
    const auto give_up = std::chrono::steady_clock::now() + kGuard;
    while (!condition()) {
      if (std::chrono::steady_clock::now() > give_up) return false;
      std::this_thread::yield();
    }
    return true;
  }

  // From now on every sleep returns at once (time stands still): a provider's
  // stop() then returns without time passing. For the end of a test.
  void release() {
    std::lock_guard lock(mutex_);
    released_ = true;
    changed_.notify_all();
  }

  // The longest a sleeper has asked to sleep, from the time it asked.
  std::int64_t longest_sleep_ns() {
    std::lock_guard lock(mutex_);
    return longest_sleep_ns_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::int64_t now_;
  std::multiset<std::int64_t> deadlines_;
  std::int64_t longest_sleep_ns_ = 0;
  bool released_ = false;
};

// Releases the clock when it goes out of scope: declared after the provider, it
// runs before the provider's destructor stops the sampling thread.
struct ReleaseAtExit {
  ManualClock& clock;
  ~ReleaseAtExit() { clock.release(); }
};

}  // namespace foveart::test
