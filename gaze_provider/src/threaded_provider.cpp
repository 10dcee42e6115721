// The sampling thread: poll the backend, queue raw samples, filter, publish.
#include "threaded_provider.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

namespace foveart::gaze {

const char* to_string(ProviderState state) noexcept {
  switch (state) {
    case ProviderState::stopped: return "stopped";
    case ProviderState::starting: return "starting";
    case ProviderState::streaming: return "streaming";
    case ProviderState::lost: return "lost";
    case ProviderState::disconnected: return "disconnected";
    case ProviderState::ended: return "ended";
  }
  return "unknown";
}

const char* to_string(EyeState state) noexcept {
  switch (state) {
    case EyeState::open: return "open";
    case EyeState::closed: return "closed";
    case EyeState::not_detected: return "not_detected";
  }
  return "unknown";
}

const char* to_string(GazeSourceKind kind) noexcept {
  switch (kind) {
    case GazeSourceKind::simulated: return "sim";
    case GazeSourceKind::replay: return "replay";
    case GazeSourceKind::fove: return "fove";
    case GazeSourceKind::hid: return "hid";
  }
  return "unknown";
}

std::shared_ptr<HostClock> steady_host_clock() {
  class Steady final : public HostClock {
   public:
    std::int64_t now_ns() noexcept override { return detail::steady_now_ns(); }
    void sleep_until_ns(std::int64_t t_ns) noexcept override {
      std::this_thread::sleep_until(std::chrono::steady_clock::time_point(std::chrono::nanoseconds(t_ns)));
    }
  };
  static const std::shared_ptr<HostClock> clock = std::make_shared<Steady>();
  return clock;
}

namespace detail {

std::int64_t steady_now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

ThreadedProvider::ThreadedProvider(std::unique_ptr<Backend> backend, const ProviderOptions& options)
    : backend_(std::move(backend)), clock_(clock_of(options)), filters_(options.filters),
      raw_(options.raw_ring_capacity) {
  status_.store(producer_status_);
}

ThreadedProvider::~ThreadedProvider() { stop(); }

bool ThreadedProvider::start(std::string* error) {
  if (thread_.joinable()) return true;
  backend_->on_start();
  producer_status_ = ProviderStatus{};
  set_state(ProviderState::starting, "waiting for the first sample");
  running_.store(true, std::memory_order_release);
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::exception& e) {
    running_.store(false);
    if (error) *error = std::string("cannot start the sampling thread: ") + e.what();
    set_state(ProviderState::stopped, "thread creation failed");
    return false;
  }
  return true;
}

void ThreadedProvider::stop() {
  running_.store(false, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  if (producer_status_.state != ProviderState::ended) set_state(ProviderState::stopped, "stopped");
}

void ThreadedProvider::set_state(ProviderState state, const std::string& reason) noexcept {
  if (state == ProviderState::disconnected && producer_status_.state != ProviderState::disconnected)
    ++producer_status_.disconnects;
  producer_status_.state = state;
  producer_status_.reason.fill('\0');
  std::memcpy(producer_status_.reason.data(), reason.data(),
              std::min(reason.size(), producer_status_.reason.size() - 1));
  status_.store(producer_status_);
}

void ThreadedProvider::run() noexcept {
  FilterChain chain(filters_);
  std::string reason;
  std::int64_t last_sample_host_ns = clock_->now_ns();
  std::uint64_t published_samples = 0;
  while (running_.load(std::memory_order_acquire)) {
    GazeSample raw;
    reason.clear();
    const PollResult r = backend_->poll(raw, reason);
    const std::int64_t now = clock_->now_ns();
    if (r == PollResult::sample) {
      if (raw.host_time_ns == 0) raw.host_time_ns = now;
      raw.source = backend_->kind();
      last_sample_host_ns = now;
      ++producer_status_.samples;
      if (!raw_.try_push(raw)) {
        if (backend_->lossless()) {
          while (!raw_.try_push(raw) && running_.load(std::memory_order_acquire))
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        } else {
          ++producer_status_.raw_dropped;
        }
      }
      const GazeSample filtered = chain.process(raw);
      history_.publish(filtered);
      if (filtered.lost) {
        if (producer_status_.state != ProviderState::lost)
          set_state(ProviderState::lost, std::string("no valid gaze for longer than the hold time (eyes ") +
                                             to_string(raw.eye_state) + ")");
      } else if (producer_status_.state != ProviderState::streaming) {
        set_state(ProviderState::streaming, "");
      }
      // Counters reach readers at least every 16 samples.
      if ((++published_samples & 15) == 0) status_.store(producer_status_);
    } else if (r == PollResult::disconnected) {
      if (producer_status_.state != ProviderState::disconnected ||
          std::strncmp(producer_status_.reason.data(), reason.c_str(), producer_status_.reason.size()) != 0) {
        chain.reset();
        set_state(ProviderState::disconnected, reason.empty() ? "device disconnected" : reason);
      }
    } else if (r == PollResult::ended) {
      set_state(ProviderState::ended, reason.empty() ? "end of trace" : reason);
      break;
    } else {  // none
      const std::int64_t hold_ns = filters_.hold.max_hold_ns;
      const bool waiting = producer_status_.state == ProviderState::streaming ||
                           producer_status_.state == ProviderState::starting;
      if (waiting && now - last_sample_host_ns > hold_ns) {
        char msg[96];
        std::snprintf(msg, sizeof msg, "no samples from the device for %lld ms",
                      static_cast<long long>((now - last_sample_host_ns) / 1'000'000));
        set_state(ProviderState::lost, msg);
      }
    }
  }
  status_.store(producer_status_);
}

std::optional<GazeSample> ThreadedProvider::latest() const {
  GazeSample s;
  if (history_.read_latest(&s, 1) == 1) return s;
  return std::nullopt;
}

std::optional<GazeSample> ThreadedProvider::sample_at(std::int64_t target_host_ns) const {
  GazeSample window[16];
  const std::size_t n = history_.read_latest(window, 16);
  GazeSample out;
  if (!predict_gaze(std::span<const GazeSample>(window, n), target_host_ns, filters_, out)) return std::nullopt;
  return out;
}

ProviderStatus ThreadedProvider::status() const {
  if (auto s = status_.load()) return *s;
  ProviderStatus busy;
  busy.state = ProviderState::starting;
  return busy;
}

std::size_t ThreadedProvider::read_raw(std::span<GazeSample> out) { return raw_.pop_into(out); }

}  // namespace detail
}  // namespace foveart::gaze
