// Per-canvas-pixel interpolation weights (issue 3): for every pixel of the
// 2W x 2H canvas the weights of its k nearest points (NeighborTable order),
// computed once from geometry so a frame of any method is a k-tap gather.
//
// Storage: k weights per pixel as float or IEEE half (half_float.hpp); indices
// stay in the NeighborTable (3 bytes each). NN stores no weights (one tap,
// weight 1). The plain RBF form (no constant term) also stores each pixel's
// weight sum, the gain the gather must keep when it renormalises.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "foveation/half_float.hpp"
#include "foveation/interpolation_weights.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"
#include "foveation/progress.hpp"

namespace foveart::foveation {

enum class WeightPrecision : std::uint8_t { f32 = 0, f16 = 1 };

// Indices + float weights above this use half weights (issue 3: 1 GB).
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
  std::vector<float> weights_f32;          // pixel-major, k per pixel (f32)
  std::vector<std::uint16_t> weights_f16;  // pixel-major, k per pixel (f16)
  std::vector<float> weight_sum;           // plain RBF only: sum of stored weights per pixel
  TableStats stats;
  double build_ms = 0.0;

  int k() const { return options.k; }
  int taps() const { return options.method == InterpMethod::nn ? 1 : options.k; }
  bool has_weights() const { return options.method != InterpMethod::nn; }
  // The weights reproduce constants, so the gather may renormalise by their sum.
  bool normalized() const { return !(is_rbf() && !options.constant_term); }
  bool is_rbf() const { return options.method == InterpMethod::rbf_mq || options.method == InterpMethod::rbf_gauss; }
  std::size_t pixel_count() const { return std::size_t(width_px) * std::size_t(height_px); }
  // Weight storage only (the indices live in the NeighborTable).
  std::size_t bytes() const {
    return weights_f32.size() * 4 + weights_f16.size() * 2 + weight_sum.size() * 4;
  }
  // Stored weight of tap j (NN: 1 for the nearest, no storage).
  float weight(std::size_t pixel, int j) const {
    if (!has_weights()) return j == 0 ? 1.0f : 0.0f;
    const std::size_t i = pixel * std::size_t(options.k) + std::size_t(j);
    return precision == WeightPrecision::f16 ? half_to_float(weights_f16[i]) : weights_f32[i];
  }
};

// Bytes of indices (3 per tap) plus weights at a precision, for a canvas and k.
std::size_t table_bytes(std::size_t canvas_pixels, int k, WeightPrecision precision);
// f32 unless indices + f32 weights exceed kTableBudgetBytes.
WeightPrecision auto_precision(std::size_t canvas_pixels, int k);

// Builds the table on `threads` std::threads (0 = hardware concurrency). Throws
// std::invalid_argument when options.k is outside 1..neighbors.k() or the
// neighbour table does not belong to `points` (canvas size).
InterpolationTable build_interpolation_table(const PointSet& points, const NeighborTable& neighbors,
                                             const InterpOptions& options,
                                             std::optional<WeightPrecision> precision = std::nullopt,
                                             int threads = 0, const ProgressFn& progress = {});

}  // namespace foveart::foveation
