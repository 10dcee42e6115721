// GazeProvider: the one interface between gaze hardware and its consumers (the
// OpenXR layer, gaze-diag). Shaped like Monado's xrt_device: consumers only see this
// class; every backend exports a single factory (backends.h) that returns nullptr
// and an error message when the device cannot be opened.
//
// Ownership: the caller owns the provider (std::unique_ptr). Destroying it stops the
// sampling thread. Samples are returned by value; nothing points into the provider.
//
// Threads: each started provider runs one sampling thread that reads the device at
// its own rate (FOVE/simulated: 120 Hz), filters each sample (filters.h) and
// publishes it without locks:
//   - latest(), sample_at(), status(): any thread, any number of threads, wait-free
//     for the producer (readers copy from a seqlock history and retry on a race);
//   - read_raw(): one consumer thread at a time (single-consumer ring buffer);
//   - start()/stop(): one controlling thread; not concurrently with each other.
// When the raw ring is full (no consumer reading) new raw samples are dropped and
// counted in ProviderStatus::raw_dropped; filtered samples are always published.
// The replay backend in as-fast-as-possible mode is the exception: it waits for room
// so that a consumer sees every sample (documented in backends.h).
//
// Units: time in int64 ns; host time is std::chrono::steady_clock (or ProviderOptions::clock).
// Errors: no exceptions cross this interface; failures are reported through return
// values and ProviderStatus::reason.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "gaze_provider/filters.h"
#include "gaze_provider/gaze_sample.h"

namespace foveart::gaze {

enum class ProviderState : std::uint8_t {
  stopped = 0,       // created or stopped; no thread
  starting = 1,      // thread running, no sample yet
  streaming = 2,     // valid (possibly held) gaze arriving
  lost = 3,          // device present but no valid gaze beyond the hold time
  disconnected = 4,  // device or service gone; the thread keeps trying to reconnect
  ended = 5,         // replay reached the end of its trace
};

const char* to_string(ProviderState state) noexcept;

// Published by the sampling thread on every state change and at least every 16
// samples (so `samples` may lag by up to 15 while streaming).
struct ProviderStatus {
  ProviderState state = ProviderState::stopped;
  std::array<char, 160> reason{};     // human-readable, NUL-terminated; empty when streaming
  std::uint64_t samples = 0;          // raw samples produced since start()
  std::uint64_t raw_dropped = 0;      // raw samples not queued because the ring was full
  std::uint64_t disconnects = 0;      // transitions into `disconnected`
  std::string reason_string() const { return std::string(reason.data()); }
};

class GazeProvider {
 public:
  virtual ~GazeProvider() = default;
  GazeProvider() = default;
  GazeProvider(const GazeProvider&) = delete;
  GazeProvider& operator=(const GazeProvider&) = delete;

  // Starts the sampling thread. Returns false (and a message) if it cannot start.
  [[nodiscard]] virtual bool start(std::string* error) = 0;
  // Stops and joins the sampling thread; idempotent. Bounded: returns within ~0.2 s.
  virtual void stop() = 0;

  // Newest filtered sample, if any was produced.
  virtual std::optional<GazeSample> latest() const = 0;
  // Filtered gaze at (interpolated) or predicted for (extrapolated) a host time;
  // see predict_gaze() in filters.h. The result's `valid` is false when gaze is lost
  // or stale: consumers then fall back to fixed foveation at the lens centre.
  virtual std::optional<GazeSample> sample_at(std::int64_t target_host_ns) const = 0;
  // Current state and counters.
  virtual ProviderStatus status() const = 0;
  // Moves unfiltered samples, oldest first, into `out`; returns how many.
  virtual std::size_t read_raw(std::span<GazeSample> out) = 0;
  // What produces the samples.
  virtual GazeSourceKind source() const = 0;
  // Nominal device rate in Hz (0 when unknown).
  virtual double nominal_rate_hz() const = 0;
};

struct ProviderOptions;  // backends.h

struct CreateResult {
  std::unique_ptr<GazeProvider> provider;  // null on failure
  std::string error;                       // why, when provider is null
  explicit operator bool() const noexcept { return provider != nullptr; }
};

// Creates a provider from a source string:
//   "sim"            simulated eye (ProviderOptions::sim)
//   "sim:SEED"       simulated eye with that seed
//   "replay:FILE"    a recorded trace (trace_csv.h), paced by ProviderOptions::replay
//   "fove"           FOVE client library (ProviderOptions::fove.library_path)
//   "hid"            first HID device with usage page 0x12 (Eye and Head Trackers)
//   "hid:VID:PID"    HID device by hexadecimal vendor/product id
// The provider is created stopped; call start().
CreateResult create_gaze_provider(std::string_view source, const ProviderOptions& options);
CreateResult create_gaze_provider(std::string_view source);

}  // namespace foveart::gaze
