// Per-canvas-pixel k nearest points (thesis 4.1), gaze-independent.
//
// For every canvas pixel centre (x + 0.5, y + 0.5) the k nearest points of the
// point set, ordered by (distance, index) so ties are deterministic. Indices are
// packed as 24-bit integers (the point set has < 2^24 points): 3 bytes per entry
// instead of the thesis's 4. Layout: pixel-major, row-major pixels, k entries each.
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "foveation/executor.hpp"
#include "foveation/point_set.hpp"
#include "foveation/progress.hpp"

namespace foveart::foveation {

inline constexpr int kMaxNeighbors = 20;

// Read-only view of a table's packed bytes; compares by content.
struct PackedBytes : std::span<const std::uint8_t> {
  using std::span<const std::uint8_t>::span;
  friend bool operator==(PackedBytes a, PackedBytes b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size()) == 0);
  }
};

class NeighborTable {
 public:
  NeighborTable() = default;

  // Builds with nanoflann on the executor's threads. Throws std::invalid_argument
  // for k outside 1..kMaxNeighbors or a point set with fewer than k points.
  static NeighborTable build(const PointSet& points, int k, Executor& executor, const ProgressFn& progress = {});

  int k() const { return k_; }
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  std::size_t pixel_count() const { return std::size_t(width_px_) * std::size_t(height_px_); }

  // j-th nearest point (0 = nearest) of canvas pixel `pixel` (= y * width + x).
  std::uint32_t neighbor(std::size_t pixel, int j) const {
    std::uint32_t v = 0;
    std::memcpy(&v, data_ + (pixel * std::size_t(k_) + std::size_t(j)) * 3, 4);
    return v & 0xFFFFFFu;
  }

  std::size_t bytes() const { return size_; }
  PackedBytes packed() const { return {data_, size_}; }

  // For the cache: adopt packed storage (validated by the caller). The second
  // form views `size` bytes at `data`, kept alive by `owner` (e.g. a file mapping).
  static NeighborTable from_packed(int width_px, int height_px, int k, std::vector<std::uint8_t> packed);
  static NeighborTable from_packed(int width_px, int height_px, int k, std::shared_ptr<const void> owner,
                                   const std::uint8_t* data, std::size_t size);

 private:
  int k_ = 0;
  int width_px_ = 0;
  int height_px_ = 0;
  // pixel_count * k * 3 bytes + 1 pad byte, immutable once built; copies share it.
  std::shared_ptr<const void> owner_;
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace foveart::foveation
