// Per-canvas-pixel interpolation weights: for every pixel of the
// 2W x 2H canvas the weights of its k nearest points (NeighborTable order),
// computed once from geometry so a frame of any method is a k-tap gather.
//
// Storage: k weights per pixel as float or IEEE half (half_float.hpp), in
// tile order, with the tile-local gather layout (gather_layout.hpp: per 8x8
// tile a palette of point indices, 1 byte per tap). NN stores neither (one
// tap, weight 1, read from the NeighborTable). The plain RBF form (no constant
// term) also stores each pixel's weight sum (row-major), the gain the gather
// must keep when it renormalises.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "foveation/gather_layout.hpp"
#include "foveation/half_float.hpp"
#include "foveation/interpolation_weights.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"
#include "foveation/progress.hpp"

namespace foveart::foveation {

enum class WeightPrecision : std::uint8_t { f32 = 0, f16 = 1 };

// Memory budget of one table (1 GB); every layout stays below it.
inline constexpr std::size_t kTableBudgetBytes = 1'000'000'000;

// What building the table met (counts of canvas pixels).
struct TableStats {
  std::uint64_t exact = 0;        // pixel centre on a point
  std::uint64_t equidistant = 0;  // MSM equal-weight rule
  std::uint64_t fallback_msm = 0; // RBF ill-conditioned or degenerate
  std::uint64_t merged = 0;       // RBF pixels with near-duplicate points merged
  std::uint64_t collinear = 0;    // RBF pixels with a collinear neighbourhood
  std::uint64_t factorizations = 0;  // RBF systems factored (the rest reused)
  double min_rcond = 1.0;
  double max_residual = 0.0;
  double max_abs_weight = 0.0;    // largest |w| stored (Lebesgue-type growth)
  double max_quantization_error = 0.0;  // max |w_stored - w| (half storage)
};

struct InterpolationTable {
  InterpOptions options;
  WeightPrecision precision = WeightPrecision::f32;
  int width_px = 0;
  int height_px = 0;
  std::vector<float> weights_f32;          // tile order (tile_ordinal), k per pixel (f32)
  std::vector<std::uint16_t> weights_f16;  // tile order (tile_ordinal), k per pixel (f16)
  std::vector<float> weight_sum;           // plain RBF only: sum of stored weights per pixel (row-major)
  GatherLayout layout;                     // palettes and 1-byte taps (empty for NN)
  TableStats stats;
  double build_ms = 0.0;

  int k() const { return options.k; }
  int taps() const { return options.method == InterpMethod::nearest ? 1 : options.k; }
  bool has_weights() const { return options.method != InterpMethod::nearest; }
  // The weights reproduce constants, so the gather may renormalise by their sum.
  bool normalized() const { return !(is_rbf() && !options.constant_term); }
  bool is_rbf() const { return options.method == InterpMethod::rbf || options.method == InterpMethod::rbf_gauss; }
  std::size_t pixel_count() const { return std::size_t(width_px) * std::size_t(height_px); }
  // Weights plus the gather layout (palettes, 1-byte taps); the NeighborTable is extra.
  std::size_t bytes() const {
    return weights_f32.size() * 4 + weights_f16.size() * 2 + weight_sum.size() * 4 + layout.bytes();
  }
  // Position of row-major canvas pixel `pixel` in the weight arrays (/ k).
  std::size_t ordinal(std::size_t pixel) const {
    const std::size_t w = std::size_t(width_px);
    return tile_ordinal(width_px, height_px, int(pixel % w), int(pixel / w));
  }
  // Stored weight of tap j of row-major canvas pixel `pixel` (NN: 1 for the nearest, no storage).
  float weight(std::size_t pixel, int j) const {
    if (!has_weights()) return j == 0 ? 1.0f : 0.0f;
    const std::size_t i = ordinal(pixel) * std::size_t(options.k) + std::size_t(j);
    return precision == WeightPrecision::f16 ? half_to_float(weights_f16[i]) : weights_f32[i];
  }
};

// Bytes of taps (1 per tap) plus weights at a precision, for a canvas and k
// (palettes add about 4 bytes per point per tile that references it).
std::size_t table_bytes(std::size_t canvas_pixels, int k, WeightPrecision precision);
// Half weights unless asked otherwise, at every k and canvas size: the gather
// streams 3 instead of 5 bytes per tap and runs faster (docs/interpolation.md,
// MSM k = 20: 23.7 vs 41.3 ms of CPU on one thread) at a weight error below
// 2e-4 that the renormalising gather keeps off constants.
inline constexpr WeightPrecision kDefaultWeightPrecision = WeightPrecision::f16;

// Builds the table on the executor's threads. Throws std::invalid_argument
// when options.k is outside 1..neighbors.k() or the neighbour table does not
// belong to `points` (canvas size).
InterpolationTable build_interpolation_table(const PointSet& points, const NeighborTable& neighbors,
                                             const InterpOptions& options, Executor& executor,
                                             std::optional<WeightPrecision> precision = std::nullopt,
                                             const ProgressFn& progress = {});

}  // namespace foveart::foveation
