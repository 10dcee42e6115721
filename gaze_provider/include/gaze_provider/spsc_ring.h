// Lock-free single-producer / single-consumer ring buffer.
//
// Threads: exactly one thread calls try_push (the producer) and exactly one thread
// calls try_pop/pop_into (the consumer); size() may be called from either. Neither
// side ever blocks or allocates after construction: when the ring is full try_push
// returns false and the producer decides (drop and count, or wait).
#pragma once

#include <atomic>
#include <cstddef>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

namespace foveart::gaze {

template <typename T>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  // Capacity is rounded up to a power of two (at least 2).
  explicit SpscRing(std::size_t capacity) {
    std::size_t c = 2;
    while (c < capacity) c <<= 1;
    slots_.resize(c);
    mask_ = c - 1;
  }

  std::size_t capacity() const noexcept { return mask_ + 1; }

  bool try_push(const T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_.load(std::memory_order_acquire) > mask_) return false;  // full
    slots_[tail & mask_] = value;
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  bool try_pop(T& out) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_.load(std::memory_order_acquire)) return false;  // empty
    out = slots_[head & mask_];
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // Pops up to out.size() elements; returns how many.
  std::size_t pop_into(std::span<T> out) noexcept {
    std::size_t n = 0;
    while (n < out.size() && try_pop(out[n])) ++n;
    return n;
  }

  std::size_t size() const noexcept {
    return tail_.load(std::memory_order_acquire) - head_.load(std::memory_order_acquire);
  }

 private:
  std::vector<T> slots_;
  std::size_t mask_ = 1;
  alignas(64) std::atomic<std::size_t> head_{0};  // next slot to read (consumer-owned)
  alignas(64) std::atomic<std::size_t> tail_{0};  // next slot to write (producer-owned)
};

}  // namespace foveart::gaze
