// Lock-free publication of the latest values from one writer to many readers.
//
// SeqlockHistory<T, N> keeps the last N values written by one producer thread.
// Readers on any thread copy values out without ever blocking the writer: a read
// that races with a write simply retries or reports the value as overwritten.
// The payload is stored in std::atomic<uint64_t> words, so the protocol is free of
// data races in the C++ memory model (and clean under ThreadSanitizer).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <type_traits>

namespace foveart::gaze {

template <typename T, std::size_t N>
class SeqlockHistory {
  static_assert(std::is_trivially_copyable_v<T>);
  static_assert(N >= 2 && (N & (N - 1)) == 0, "N must be a power of two");
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;

  struct Slot {
    std::atomic<std::uint64_t> seq{0};  // 2*(index+1) when holding value `index`; odd while written
    std::array<std::atomic<std::uint64_t>, kWords> words{};
  };

 public:
  static constexpr std::size_t capacity = N;

  // Writer thread only.
  void publish(const T& value) noexcept {
    const std::uint64_t index = count_.load(std::memory_order_relaxed);
    Slot& slot = slots_[index & (N - 1)];
    std::array<std::uint64_t, kWords> raw{};
    std::memcpy(raw.data(), &value, sizeof(T));
    slot.seq.store(2 * index + 1, std::memory_order_relaxed);
    // Release on every word: a reader that sees any new word also sees the odd seq.
    for (std::size_t i = 0; i < kWords; ++i) slot.words[i].store(raw[i], std::memory_order_release);
    slot.seq.store(2 * (index + 1), std::memory_order_release);
    count_.store(index + 1, std::memory_order_release);
  }

  // Number of values ever published (any thread).
  std::uint64_t count() const noexcept { return count_.load(std::memory_order_acquire); }

  // Value number `index` (0-based), if it is still held and not being overwritten.
  std::optional<T> read(std::uint64_t index) const noexcept {
    const Slot& slot = slots_[index & (N - 1)];
    for (int attempt = 0; attempt < 4; ++attempt) {
      const std::uint64_t s1 = slot.seq.load(std::memory_order_acquire);
      if (s1 != 2 * (index + 1)) return std::nullopt;  // overwritten, or not yet written
      std::array<std::uint64_t, kWords> raw{};
      for (std::size_t i = 0; i < kWords; ++i) raw[i] = slot.words[i].load(std::memory_order_acquire);
      if (slot.seq.load(std::memory_order_relaxed) == s1) {
        T value;
        std::memcpy(static_cast<void*>(&value), raw.data(), sizeof(T));
        return value;
      }
    }
    return std::nullopt;
  }

  // Copies the newest values, newest first, into out[0..]; returns how many.
  std::size_t read_latest(T* out, std::size_t max_count) const noexcept {
    const std::uint64_t n = count();
    std::size_t got = 0;
    for (std::uint64_t k = 0; k < max_count && k < n && k < N - 1; ++k) {
      const auto v = read(n - 1 - k);
      if (!v) break;
      out[got++] = *v;
    }
    return got;
  }

 private:
  std::array<Slot, N> slots_{};
  std::atomic<std::uint64_t> count_{0};
};

// A single value published by one writer and read by many (same protocol).
template <typename T>
class SeqlockCell {
 public:
  void store(const T& value) noexcept { history_.publish(value); }
  std::optional<T> load() const noexcept {
    for (int attempt = 0; attempt < 64; ++attempt) {
      const std::uint64_t n = history_.count();
      if (n == 0) return std::nullopt;
      if (auto v = history_.read(n - 1)) return v;
    }
    return std::nullopt;
  }

 private:
  SeqlockHistory<T, 4> history_;
};

}  // namespace foveart::gaze
