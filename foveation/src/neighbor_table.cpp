// k nearest points per canvas pixel (thesis 4.1), built with nanoflann's k-d tree.
#include "foveation/neighbor_table.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <optional>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>

#include "point_kd_tree.hpp"
#include <sys/mman.h>

namespace foveart::foveation {
namespace {

using KdTree = PointKdTree<double>;

// Pixels are processed in square tiles. Every pixel q of a tile with centre c
// and half-diagonal h has its k nearest points within d_k(c) + 2h of c (they lie
// within d_k(q) <= d_k(c) + h of q), so one radius search per tile yields a
// candidate set that provably contains each pixel's k nearest, ties included.
constexpr int kTilePx = 8;

// A candidate's sort key: exact squared distance (a non-negative double, whose
// bit pattern orders like its value) above its index, so one integer
// comparison orders by (distance, index).
__extension__ typedef unsigned __int128 Key;

Key make_key(double d2, std::uint32_t index) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &d2, sizeof bits);
  return (Key(bits) << 64) | Key(index);
}

double key_distance2(Key key) {
  const auto bits = std::uint64_t(key >> 64);
  double d2 = 0.0;
  std::memcpy(&d2, &bits, sizeof d2);
  return d2;
}

void put24(std::uint8_t* dst, std::uint32_t v) {
  dst[0] = std::uint8_t(v & 0xFF);
  dst[1] = std::uint8_t((v >> 8) & 0xFF);
  dst[2] = std::uint8_t((v >> 16) & 0xFF);
}

class TileQuery {
 public:
  TileQuery(const KdTree& tree, const std::vector<glm::vec2>& pts, int k)
      : tree_(tree), pts_(pts), k_(k), idx_(std::size_t(k)), dist_(std::size_t(k)) {}

  // Writes the k nearest of every pixel of the tile [x0, x1) x [y0, y1).
  void run(int x0, int y0, int x1, int y1, int width_px, std::uint8_t* packed) {
    const double cx = 0.5 * (x0 + x1);
    const double cy = 0.5 * (y0 + y1);
    const double h = 0.5 * std::hypot(double(x1 - x0), double(y1 - y0));
    const float c[2] = {float(cx), float(cy)};
    const std::size_t found = tree_.knnSearch(c, std::size_t(k_), idx_.data(), dist_.data());
    double dk = 0.0;
    for (std::size_t i = 0; i < found; ++i) {
      const glm::vec2 p = pts_[idx_[i]];
      dk = std::max(dk, std::hypot(double(p.x) - cx, double(p.y) - cy));
    }
    // Where points are dense the tile's own size dominates the candidate radius:
    // split it, so each pixel scans fewer hits (the threshold is measured).
    if (dk < 0.5 * h && x1 - x0 > 1 && y1 - y0 > 1) {
      const int xm = (x0 + x1) / 2;
      const int ym = (y0 + y1) / 2;
      run(x0, y0, xm, ym, width_px, packed);
      run(xm, y0, x1, ym, width_px, packed);
      run(x0, ym, xm, y1, width_px, packed);
      run(xm, ym, x1, y1, width_px, packed);
      return;
    }
    // Margin covers the float rounding of the tree's own distance test.
    const double radius = dk + 2.0 * h + 1e-3;
    hits_.clear();
    tree_.radiusSearch(c, radius * radius, hits_, nanoflann::SearchParams(32, 0.0f, false));
    ord_.resize(hits_.size());
    for (std::size_t i = 0; i < hits_.size(); ++i) ord_[i] = hits_[i].first;
    // Serpentine walk: a pixel's k nearest lie within d_k(previous pixel) + 1 px,
    // and taken in the previous pixel's order those few candidates are nearly
    // sorted, so insertion sort costs ~their count. Far hits keep their order.
    bool first = true;
    double prev_dk = 0.0;
    for (int y = y0; y < y1; ++y) {
      const bool forward = ((y - y0) & 1) == 0;
      for (int i = 0; i < x1 - x0; ++i) {
        const int x = forward ? x0 + i : x1 - 1 - i;
        const double qx = double(x) + 0.5;
        const double qy = double(y) + 0.5;
        // Rounding slack: the bound is compared with rounded squared distances.
        const double bound = first ? dk + std::hypot(qx - cx, qy - cy) : prev_dk + 1.0;
        select(qx, qy, (bound * bound) * (1.0 + 1e-9) + 1e-9);
        first = false;
        std::uint8_t* dst = packed + (std::size_t(y) * std::size_t(width_px) + std::size_t(x)) * std::size_t(k_) * 3;
        for (int j = 0; j < k_; ++j) put24(dst + 3 * j, std::uint32_t(cand_[std::size_t(j)]));
        const double dk2 = key_distance2(cand_[std::size_t(k_ - 1)]);
        prev_dk = std::sqrt(dk2);
      }
    }
  }

 private:
  // Sorts the hits within squared distance `bound2` of q into cand_ by
  // (distance, index); reorders ord_ as cand_ followed by the other hits.
  void select(double qx, double qy, double bound2) {
    cand_.clear();
    rest_.clear();
    for (const std::uint32_t index : ord_) {
      const glm::vec2 p = pts_[index];
      const double dx = double(p.x) - qx;
      const double dy = double(p.y) - qy;
      const double d2 = dx * dx + dy * dy;
      if (d2 <= bound2) {
        cand_.push_back(make_key(d2, index));
      } else {
        rest_.push_back(index);
      }
    }
    if (cand_.size() < std::size_t(k_)) {
      // Cannot happen (the bound holds); stay exact regardless.
      select(qx, qy, std::numeric_limits<double>::infinity());
      return;
    }
    for (std::size_t j = 1; j < cand_.size(); ++j) {
      const Key v = cand_[j];
      std::size_t m = j;
      for (; m > 0 && cand_[m - 1] > v; --m) cand_[m] = cand_[m - 1];
      cand_[m] = v;
    }
    std::size_t o = 0;
    for (const Key key : cand_) ord_[o++] = std::uint32_t(key);
    for (const std::uint32_t index : rest_) ord_[o++] = index;
  }

  const KdTree& tree_;
  const std::vector<glm::vec2>& pts_;
  int k_;
  std::vector<std::uint32_t> idx_;
  std::vector<double> dist_;
  std::vector<std::pair<std::uint32_t, double>> hits_;
  std::vector<std::uint32_t> ord_, rest_;
  std::vector<Key> cand_;
};

}  // namespace

NeighborTable NeighborTable::build(const PointSet& points, int k, Executor& executor, const ProgressFn& progress) {
  if (k < 1 || k > kMaxNeighbors) {
    throw std::invalid_argument("k must be in 1.." + std::to_string(kMaxNeighbors) + " (got " +
                                std::to_string(k) + ")");
  }
  if (points.size() < std::size_t(k)) {
    throw std::invalid_argument("point set has " + std::to_string(points.size()) +
                                " points, fewer than k = " + std::to_string(k));
  }
  if (points.size() >= (1u << 24)) throw std::invalid_argument("point set exceeds 2^24 points");

  NeighborTable t;
  t.k_ = k;
  t.width_px_ = points.canvas_width_px;
  t.height_px_ = points.canvas_height_px;
  // Every entry is written below. Anonymous memory asked for transparent huge
  // pages: faulting in 442 MB as 2 MB pages instead of 4 KB ones saves ~0.5 s
  // of kernel time on the build threads (the 4 KB fallback still works).
  t.size_ = t.pixel_count() * std::size_t(k) * 3 + 1;
  void* mem = mmap(nullptr, t.size_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mem == MAP_FAILED) throw std::bad_alloc();
  madvise(mem, t.size_, MADV_HUGEPAGE);  // advice only: failure leaves 4 KB pages
  const std::size_t mapped_bytes = t.size_;
  std::shared_ptr<std::uint8_t> storage(static_cast<std::uint8_t*>(mem),
                                        [mapped_bytes](std::uint8_t* p) { munmap(p, mapped_bytes); });
  std::uint8_t* out = storage.get();
  out[t.size_ - 1] = 0;  // pad byte read by the last entry's 4-byte load
  t.data_ = out;
  t.owner_ = std::move(storage);

  PointCloud cloud{&points.position_px};
  KdTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();

  const int tile_rows = (t.height_px_ + kTilePx - 1) / kTilePx;
  std::atomic<int> rows_done{0};
  std::vector<std::optional<TileQuery>> queries(executor.thread_count());  // per worker slot
  executor.parallel_for(std::size_t(tile_rows), [&](std::size_t ty, unsigned worker) {
    auto& query = queries[worker];
    if (!query) query.emplace(tree, points.position_px, k);
    const int y0 = int(ty) * kTilePx;
    const int y1 = std::min(y0 + kTilePx, t.height_px_);
    for (int x0 = 0; x0 < t.width_px_; x0 += kTilePx) {
      query->run(x0, y0, std::min(x0 + kTilePx, t.width_px_), y1, t.width_px_, out);
    }
    const int done = rows_done.fetch_add(1) + 1;
    if (worker == 0 && progress && (done & 15) == 0) progress(double(done) / double(tile_rows));  // the caller's thread
  });
  if (progress) progress(1.0);
  return t;
}

NeighborTable NeighborTable::from_packed(int width_px, int height_px, int k, std::vector<std::uint8_t> packed) {
  auto owner = std::make_shared<const std::vector<std::uint8_t>>(std::move(packed));
  return from_packed(width_px, height_px, k, owner, owner->data(), owner->size());
}

NeighborTable NeighborTable::from_packed(int width_px, int height_px, int k, std::shared_ptr<const void> owner,
                                         const std::uint8_t* data, std::size_t size) {
  // Divide instead of multiplying: dimensions from a file must not wrap into a matching size.
  const std::size_t entry_bytes = std::size_t(k) * 3;
  const bool size_matches = k >= 1 && k <= kMaxNeighbors && width_px > 0 && height_px > 0 && size >= 1 &&
                            (size - 1) % entry_bytes == 0 && (size - 1) / entry_bytes % std::size_t(width_px) == 0 &&
                            (size - 1) / entry_bytes / std::size_t(width_px) == std::size_t(height_px);
  if (data == nullptr || !size_matches) {
    throw std::invalid_argument("table dimensions " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                                ", k " + std::to_string(k) + " do not match the packed size (" + std::to_string(size) +
                                " bytes)");
  }
  NeighborTable t;
  t.k_ = k;
  t.width_px_ = width_px;
  t.height_px_ = height_px;
  t.owner_ = std::move(owner);
  t.data_ = data;
  t.size_ = size;
  return t;
}

}  // namespace foveart::foveation
