// Nested levels of a point set (point_levels.hpp): greedy Poisson-disc acceptance per
// level with nanoflann's k-d tree, then each thinned point's nearest level-0 points.
#include "foveation/point_levels.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "point_kd_tree.hpp"

namespace foveart::foveation {
namespace {

using LevelKdTree = PointKdTree<float>;

constexpr std::uint8_t kUnassigned = 0xFF;

// Level `l` takes, in the set's order, each unassigned point with no point of level <= l
// within kLevelSpacing[l] times its radius. The pixel grid is level 0 whole.
void assign_level(const PointSet& points, const LevelKdTree& tree, std::uint8_t l, std::vector<std::uint8_t>& level) {
  std::vector<std::pair<std::uint32_t, float>> hits;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (level[i] != kUnassigned) continue;
    if (l == 0 && points.on_pixel_grid(i)) {
      level[i] = 0;
      continue;
    }
    const float r = kLevelSpacing[l] * points.radius_px[i];
    const float query[2] = {points.position_px[i].x, points.position_px[i].y};
    // Strictly inside r: a point at exactly the spacing does not block.
    tree.radiusSearch(query, r * r * (1.0f - 1e-6f), hits, nanoflann::SearchParams(32, 0.0f, false));
    const bool blocked = std::any_of(hits.begin(), hits.end(), [&](const auto& h) {
      return h.first != i && level[h.first] <= l;
    });
    if (!blocked) level[i] = l;
  }
}

// Per point above level 0, its kParents nearest level-0 points, weighted by 1 / d^2.
void find_parents(const PointSet& points, PointLevels& out, Executor& executor) {
  std::vector<glm::vec2> coarse_px;
  std::vector<std::uint32_t> coarse_index;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (out.level[i] == 0) coarse_px.push_back(points.position_px[i]), coarse_index.push_back(std::uint32_t(i));
  out.parent.assign(points.size(), {PointLevels::kNoParent, PointLevels::kNoParent, PointLevels::kNoParent});
  out.parent_weight.assign(points.size(), {0.0f, 0.0f, 0.0f});
  if (coarse_px.empty()) return;
  PointCloud cloud{&coarse_px};
  LevelKdTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  constexpr std::size_t kChunk = 4096;
  executor.parallel_for((points.size() + kChunk - 1) / kChunk, [&](std::size_t chunk) {
    std::uint32_t found[PointLevels::kParents];
    float d2[PointLevels::kParents];
    const std::size_t end = std::min(points.size(), (chunk + 1) * kChunk);
    for (std::size_t i = chunk * kChunk; i < end; ++i) {
      if (out.level[i] == 0) continue;
      const float query[2] = {points.position_px[i].x, points.position_px[i].y};
      const std::size_t n = tree.knnSearch(query, PointLevels::kParents, found, d2);
      float sum = 0.0f;
      for (std::size_t j = 0; j < n; ++j) sum += out.parent_weight[i][j] = 1.0f / std::max(d2[j], 1e-6f);
      for (std::size_t j = 0; j < n; ++j) {
        out.parent[i][j] = coarse_index[found[j]];
        out.parent_weight[i][j] /= sum;
      }
    }
  });
}

}  // namespace

std::size_t PointLevels::count_at_or_below(std::uint8_t l) const {
  return std::size_t(std::count_if(level.begin(), level.end(), [l](std::uint8_t v) { return v <= l; }));
}

PointLevels build_point_levels(const PointSet& points, Executor& executor) {
  PointLevels out;
  out.level.assign(points.size(), kUnassigned);
  PointCloud cloud{&points.position_px};
  LevelKdTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  for (std::uint8_t l = 0; l < PointLevels::kFinest; ++l) assign_level(points, tree, l, out.level);
  for (std::uint8_t& l : out.level)
    if (l == kUnassigned) l = PointLevels::kFinest;
  find_parents(points, out, executor);
  return out;
}

}  // namespace foveart::foveation
