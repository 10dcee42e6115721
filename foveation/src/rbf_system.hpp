// Factored RBF system of one neighbourhood (thesis eqs. 7-10), reusable for
// every query whose k nearest points are the same set. Private to foveation.
#pragma once

#include <array>
#include <span>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "foveation/interpolation_weights.hpp"
#include "foveation/neighbor_table.hpp"

namespace foveart::foveation::detail {

inline constexpr int kMaxSystem = kMaxNeighbors + 1;
using SysMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxSystem, kMaxSystem>;
using SysVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxSystem, 1>;

class RbfSystem {
 public:
  // Factors the system of `points` (at most kMaxNeighbors). The order given is the
  // canonical order: near-duplicates merge into the earlier one.
  void factor(const InterpOptions& options, std::span<const Vec2d> points);

  // False when the neighbourhood is degenerate or too ill-conditioned (use MSM).
  bool usable() const { return usable_; }
  double rcond() const { return rcond_; }
  int merged() const { return n_ - m_; }
  bool collinear() const { return collinear_; }

  // Cardinal weights at `query` in the order of factor()'s points. Returns the
  // relative residual ||M w - b|| / ||b||, +inf when a weight is not finite.
  double solve(Vec2d query, std::span<double> out) const;

 private:
  double kernel(double r2) const;  // of the squared scaled distance

  bool gaussian_ = false;
  bool constant_ = true;
  double eps_ = 1.0;
  Vec2d centre_{};
  double inv_h_ = 1.0;
  int n_ = 0;  // points given
  int m_ = 0;  // points after merging near-duplicates
  std::array<int, kMaxNeighbors> active_{};  // given index of each active point
  std::array<Vec2d, kMaxNeighbors> u_{};     // scaled coordinates of the active points
  SysMatrix system_;                         // [A 1; 1^T 0] or A
  Eigen::PartialPivLU<SysMatrix> lu_;        // multiquadric
  Eigen::LLT<SysMatrix> llt_;                // Gaussian: A only
  SysVector z_;                              // Gaussian + constant: A^-1 1
  double one_z_ = 0.0;                       // 1^T A^-1 1
  double rcond_ = 0.0;
  bool usable_ = false;
  bool collinear_ = false;
};

// A factored system kept for the next query with the same neighbour set.
struct RbfCache {
  RbfSystem system;
  std::array<std::uint32_t, kMaxNeighbors> ids{};
  int n = -1;
  std::size_t hits = 0;
  std::size_t misses = 0;
};

// interpolation_weights() with an optional cache: the factorisation depends only
// on the set of ids (canonical ascending order), so a hit gives identical bits.
WeightInfo weights_cached(const InterpOptions& options, std::span<const Vec2d> neighbors,
                          std::span<const std::uint32_t> ids, Vec2d query, std::span<double> out,
                          RbfCache* cache);

}  // namespace foveart::foveation::detail
