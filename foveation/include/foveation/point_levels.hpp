// Nested levels of a point set, so that a frame can thin its points where the content
// is flat by a test per point, never a rebuild (thesis 8.2: density that follows the
// content). Level 0 is a Poisson subset at three times the set's spacing (about a ninth
// of the points), level 1 adds points down to twice it (about a quarter), level 2 down
// to sqrt(2) times it (about half), level 3 is the rest. The pixel grid (the pixel-exact
// fovea and the margin a denser scale adds to it) is level 0 throughout, so it is always
// traced: filling a grid point from its neighbours would blur what the grid shows sharp.
//
// A point above level 0 keeps its nearest level-0 points and their inverse-distance
// weights (Shepard 1968): a frame that does not trace it gives it their colour, so the
// reconstruction's tables stay those of the whole set.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "foveation/executor.hpp"
#include "foveation/point_set.hpp"

namespace foveart::foveation {

struct PointLevels {
  static constexpr std::uint8_t kLevels = 4;
  static constexpr std::uint8_t kFinest = kLevels - 1;
  static constexpr std::uint32_t kParents = 3;
  static constexpr std::uint32_t kNoParent = 0xFFFFFFFFu;

  std::vector<std::uint8_t> level;  // per point, 0 (coarsest) to kFinest
  // Per point above level 0: its nearest level-0 points (kNoParent: fewer), weights summing to 1.
  std::vector<std::array<std::uint32_t, kParents>> parent;
  std::vector<std::array<float, kParents>> parent_weight;

  std::size_t size() const { return level.size(); }
  std::size_t count_at_or_below(std::uint8_t l) const;  // points a tile of level l traces, over the whole set
};

// Levels by greedy Poisson-disc acceptance in the set's (Hilbert) order: level L takes a
// point when no point of level <= L lies within kLevelSpacing[L] times its disc radius.
// Deterministic for the set.
PointLevels build_point_levels(const PointSet& points, Executor& executor);

// Spacing of each level's subset in units of a point's disc radius (the finest: the set's own).
inline constexpr float kLevelSpacing[PointLevels::kLevels] = {3.0f, 2.0f, 1.41421356f, 0.0f};

}  // namespace foveart::foveation
