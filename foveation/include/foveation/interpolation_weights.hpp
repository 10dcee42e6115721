// Weights of one query point from its k nearest scattered points (thesis 4.3):
// nearest neighbour, modified Shepard (Renka 1988, thesis eqs. 5-6) and radial
// basis functions (thesis eqs. 7-10) with multiquadric or Gaussian kernels.
//
// Pure math, double precision, no state. Every method returns k weights so a
// value is s(q) = sum_i w_i f_i; the renderer precomputes these per canvas pixel
// (interpolation_table.hpp) and a frame is a k-tap gather (gather.hpp).
//
// Rules (docs/interpolation.md):
// - Neighbours come nearest first, exact distance ties by ascending point index
//   (the NeighborTable order). NN picks the first minimal distance: lowest index.
// - MSM weights ((R - h)+ / (R h))^2, R = distance of the farthest neighbour,
//   evaluated as ((1 - h/R)+ * h_min/h)^2 (same ratios, every factor in [0, 1],
//   cannot go negative or overflow). h == 0 returns that point exactly. When
//   every neighbour is at distance R (weight sum 0) the weights are equal (1/k).
// - RBF: coordinates centred on the neighbours' centroid and divided by the
//   local spacing h_local = rms radius * sqrt(2 pi / k); shape eps = eps0 / h_local.
//   With the constant term (default) the system [A 1; 1^T 0] reproduces
//   constants; `constant_term = false` is the thesis's plain form A w = phi.
//   Multiquadric: partial-pivoting LU (the matrix is indefinite); Gaussian:
//   Cholesky of A (positive definite), constant term by Schur complement.
//   Points closer than kDuplicateTolerance * h_local are merged (the first in
//   neighbour order keeps the weight). rcond < rcond_min, a relative residual
//   above residual_max or a non-finite weight falls back to MSM weights.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace foveart::foveation {

enum class InterpMethod : std::uint8_t { nearest = 0, msm = 1, rbf = 2, rbf_gauss = 3 };

// "nearest", "msm", "rbf" (multiquadric), "rbf-gauss": the layer config's
// "interpolation" values, and the tools' --interpolation (rbf-gauss: tools only).
std::string_view method_name(InterpMethod method);
std::optional<InterpMethod> parse_method(std::string_view name);

struct InterpOptions {
  InterpMethod method = InterpMethod::msm;
  int k = 5;                    // taps per query, 1..kMaxNeighbors
  double shape = 0.0;           // eps0 = eps * h_local; 0 = kernel default
  bool constant_term = true;    // RBF: augment with a constant (false: thesis form)
  double rcond_min = 1e-13;     // RBF: reciprocal condition estimate below -> MSM
  double residual_max = 1e-9;   // RBF: ||M w - b|| / ||b|| above -> MSM
};

// eps0 used when InterpOptions::shape is 0: 0.2 for both kernels.
double default_shape(InterpMethod method);
inline double effective_shape(const InterpOptions& o) { return o.shape > 0.0 ? o.shape : default_shape(o.method); }

// Positions closer than this times h_local count as one point for RBF.
inline constexpr double kDuplicateTolerance = 1e-6;

struct Vec2d {
  double x = 0.0;
  double y = 0.0;
};

enum class WeightStatus : std::uint8_t {
  ok = 0,            // the method's weights
  exact = 1,         // query on a point (h == 0): weight 1 there
  equidistant = 2,   // MSM: all neighbours at the same distance, equal weights
  fallback_msm = 3,  // RBF: degenerate or ill-conditioned, MSM weights instead
};

struct WeightInfo {
  WeightStatus status = WeightStatus::ok;
  double rcond = 1.0;     // RBF: reciprocal condition estimate of the solved matrix
  double residual = 0.0;  // RBF: ||M w - b|| / ||b||
  int merged = 0;         // RBF: near-duplicate points merged away
  bool collinear = false; // RBF: the neighbourhood is (numerically) on a line
};

// Weights for `query` from `neighbors` (nearest first, distance ties by id),
// written to out[0..n). `ids` (point indices, may be empty = list positions)
// fix the canonical order of the RBF system so that a table and a single query
// agree bit for bit. Requires 1 <= n <= kMaxNeighbors, n == out.size() (== ids.size()
// when given) and finite coordinates; throws std::invalid_argument otherwise.
WeightInfo interpolation_weights(const InterpOptions& options, std::span<const Vec2d> neighbors,
                                 std::span<const std::uint32_t> ids, Vec2d query,
                                 std::span<double> out);
inline WeightInfo interpolation_weights(const InterpOptions& options, std::span<const Vec2d> neighbors,
                                        Vec2d query, std::span<double> out) {
  return interpolation_weights(options, neighbors, {}, query, out);
}

// MSM weights alone (also the RBF fallback); returns exact / equidistant / ok.
WeightStatus msm_weights(std::span<const Vec2d> neighbors, Vec2d query, std::span<double> out);

// The MSM weight before normalisation, as computed for the table (thesis eq. 6
// squared, Renka 1988): ((1 - h/R)+ * (h_min/h))^2. Templated so tests can show
// it stays >= 0 in float. Requires 0 < h_min <= h, R > 0.
template <typename T>
inline T msm_weight(T h, T h_min, T radius) {
  const T t = T(1) - h / radius;
  const T a = t > T(0) ? t : T(0);
  const T b = h_min / h;
  const T v = a * (b < T(1) ? b : T(1));
  return v * v;
}

// s(q) = sum w_i f_i, the interpolant of one channel from precomputed weights.
double apply_weights(std::span<const double> weights, std::span<const double> values);

}  // namespace foveart::foveation
