// A host clock that moves only when its owner moves it (gaze_provider/host_clock.h):
// a provider's sampling thread sleeps on it until then. The layer steps it to each
// frame's display time under a simulated runtime's virtual clock ("gaze_clock":
// "display_time"), so that a replayed gaze stays in step with the frames whatever the
// machine's load; tests drive providers with it so that no pass/fail check waits on
// real time. Real time appears only in guards: a wait that gives up after kGuard
// reports failure, it never acts as though time had come.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <set>

#include "gaze_provider/host_clock.h"

namespace foveart::gaze {

class SteppedClock final : public HostClock {
 public:
  static constexpr std::chrono::seconds kGuard{20};

  explicit SteppedClock(std::int64_t start_ns = 1'000'000'000) : now_(start_ns) {}

  std::int64_t now_ns() noexcept override;
  void sleep_until_ns(std::int64_t t_ns) noexcept override;

  // Moves time to t_ns (never back) and wakes the sleepers it reaches.
  void advance_to(std::int64_t t_ns);

  // Waits until `done` holds or some thread sleeps past now: whatever was due by
  // now has been done. False when neither happens within kGuard of real time.
  [[nodiscard]] bool settle(const std::function<bool()>& done = {});

  // Steps time from sleeper deadline to sleeper deadline up to t_ns, letting the
  // sleepers act at each, as a perfectly punctual scheduler would; then settles.
  // Stops early, time where it is, once `done` holds (a provider that ended and
  // sleeps no more). False when a step does not settle (see settle).
  [[nodiscard]] bool run_until(std::int64_t t_ns, const std::function<bool()>& done = {});

  // Waits (real time, at most kGuard) until `condition` holds, for what other
  // threads do without sleeping on this clock. False when it never does.
  [[nodiscard]] static bool eventually(const std::function<bool()>& condition);

  // From now on every sleep returns at once (time stands still): a provider's
  // stop() then returns without time passing.
  void release();

  // The longest a sleeper has asked to sleep, from the time it asked.
  std::int64_t longest_sleep_ns();

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::int64_t now_;
  std::multiset<std::int64_t> deadlines_;
  std::int64_t longest_sleep_ns_ = 0;
  bool released_ = false;
};

}  // namespace foveart::gaze
