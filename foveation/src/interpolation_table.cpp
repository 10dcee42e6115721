#include "foveation/interpolation_table.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rbf_system.hpp"

namespace foveart::foveation {

std::size_t table_bytes(std::size_t canvas_pixels, int k, WeightPrecision precision) {
  const std::size_t per_tap = 1 + (precision == WeightPrecision::f16 ? 2 : 4);
  return canvas_pixels * std::size_t(k) * per_tap;
}

namespace {

void merge_stats(TableStats& into, const TableStats& s) {
  into.exact += s.exact;
  into.equidistant += s.equidistant;
  into.fallback_msm += s.fallback_msm;
  into.merged += s.merged;
  into.collinear += s.collinear;
  into.factorizations += s.factorizations;
  into.min_rcond = std::min(into.min_rcond, s.min_rcond);
  into.max_residual = std::max(into.max_residual, s.max_residual);
  into.max_abs_weight = std::max(into.max_abs_weight, s.max_abs_weight);
  into.max_quantization_error = std::max(into.max_quantization_error, s.max_quantization_error);
}

// Weights of canvas rows [y0, y1) into the table; everything a row needs is local.
void build_rows(const PointSet& points, const NeighborTable& nt, InterpolationTable& t, int y0, int y1,
                TableStats& stats) {
  const int k = t.options.k;
  const bool rbf = t.is_rbf();
  detail::RbfCache cache;
  std::array<Vec2d, kMaxNeighbors> nb{};
  std::array<std::uint32_t, kMaxNeighbors> ids{};
  std::array<double, kMaxNeighbors> w{};
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < t.width_px; ++x) {
      const std::size_t pixel = std::size_t(y) * std::size_t(t.width_px) + std::size_t(x);
      for (int j = 0; j < k; ++j) {
        ids[std::size_t(j)] = nt.neighbor(pixel, j);
        const auto p = points.position_px[ids[std::size_t(j)]];
        nb[std::size_t(j)] = {double(p.x), double(p.y)};
      }
      const Vec2d q{x + 0.5, y + 0.5};
      const auto span_n = std::span<const Vec2d>(nb.data(), std::size_t(k));
      const auto span_w = std::span<double>(w.data(), std::size_t(k));
      const auto span_i = std::span<const std::uint32_t>(ids.data(), std::size_t(k));
      const auto info = detail::weights_cached(t.options, span_n, span_i, q, span_w, rbf ? &cache : nullptr);
      stats.exact += info.status == WeightStatus::exact;
      stats.equidistant += info.status == WeightStatus::equidistant;
      if (rbf && info.status != WeightStatus::exact) {
        stats.fallback_msm += info.status == WeightStatus::fallback_msm;
        stats.merged += info.merged > 0;
        stats.collinear += info.collinear;
        stats.min_rcond = std::min(stats.min_rcond, info.rcond);
        if (info.status == WeightStatus::ok) stats.max_residual = std::max(stats.max_residual, info.residual);
      }
      float sum = 0.0f;
      const std::size_t base = tile_ordinal(t.width_px, t.height_px, x, y) * std::size_t(k);
      for (int j = 0; j < k; ++j) {
        const double wj = w[std::size_t(j)];
        stats.max_abs_weight = std::max(stats.max_abs_weight, std::abs(wj));
        float stored = float(wj);
        if (t.precision == WeightPrecision::f16) {
          const std::uint16_t h = float_to_half(stored);
          t.weights_f16[base + std::size_t(j)] = h;
          stored = half_to_float(h);
        } else {
          t.weights_f32[base + std::size_t(j)] = stored;
        }
        stats.max_quantization_error = std::max(stats.max_quantization_error, std::abs(double(stored) - wj));
        sum += stored;
      }
      if (!t.weight_sum.empty()) t.weight_sum[pixel] = sum;
    }
  }
  stats.factorizations += cache.misses;
}

}  // namespace

InterpolationTable build_interpolation_table(const PointSet& points, const NeighborTable& neighbors,
                                             const InterpOptions& options, Executor& executor,
                                             std::optional<WeightPrecision> precision, const ProgressFn& progress) {
  if (options.k < 1 || options.k > neighbors.k()) {
    throw std::invalid_argument("interpolation table: k = " + std::to_string(options.k) +
                                " outside 1.." + std::to_string(neighbors.k()) + " (the neighbour table's k)");
  }
  if (neighbors.width_px() != points.canvas_width_px || neighbors.height_px() != points.canvas_height_px) {
    throw std::invalid_argument("interpolation table: neighbour table canvas " +
                                std::to_string(neighbors.width_px()) + "x" + std::to_string(neighbors.height_px()) +
                                " does not match the point set's " + std::to_string(points.canvas_width_px) + "x" +
                                std::to_string(points.canvas_height_px));
  }
  const auto start = std::chrono::steady_clock::now();
  InterpolationTable t;
  t.options = options;
  t.options.shape = effective_shape(options);
  t.width_px = neighbors.width_px();
  t.height_px = neighbors.height_px();
  t.precision = precision.value_or(kDefaultWeightPrecision);
  if (t.has_weights()) {
    const std::size_t n = t.pixel_count() * std::size_t(options.k);
    if (t.precision == WeightPrecision::f16) {
      t.weights_f16.resize(n);
    } else {
      t.weights_f32.resize(n);
    }
    if (!t.normalized()) t.weight_sum.resize(t.pixel_count());
    auto stats = std::vector<TableStats>(executor.thread_count());  // per worker slot
    std::atomic<int> rows_done{0};
    // Bands of 16 rows handed out in order balance the dense fovea across threads.
    constexpr int kBand = 16;
    executor.parallel_for(std::size_t((t.height_px + kBand - 1) / kBand), [&](std::size_t band, unsigned worker) {
      const int y0 = int(band) * kBand;
      const int y1 = std::min(t.height_px, y0 + kBand);
      build_rows(points, neighbors, t, y0, y1, stats[worker]);
      const int done = rows_done.fetch_add(y1 - y0) + (y1 - y0);
      if (worker == 0 && progress) progress(double(done) / double(t.height_px));  // the caller's thread
    });
    for (const auto& s : stats) merge_stats(t.stats, s);
    t.layout = build_gather_layout(neighbors, options.k, executor);
  }
  if (progress) progress(1.0);
  t.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return t;
}

}  // namespace foveart::foveation
