#include "foveation/content_density.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace foveart::foveation {
float tile_contrast(float min_luminance, float max_luminance, float dark_luminance) {
  if (!(max_luminance >= min_luminance)) return 0.0f;  // no observation (or NaN)
  return (max_luminance - min_luminance) / std::max(max_luminance + min_luminance + 2.0f * dark_luminance, 1e-12f);
}

std::uint8_t level_for_contrast(float contrast, const ContentDensityOptions& options) {
  if (!options.thins() || contrast >= options.full_contrast) return PointLevels::kFinest;
  // Each level halves the contrast it needs: level l from full_contrast / 2^(kFinest - l).
  std::uint8_t level = PointLevels::kFinest - 1;
  for (float needed = 0.5f * options.full_contrast; level > 0 && contrast < needed; needed *= 0.5f) --level;
  return level;
}

ContentDensity::ContentDensity(const PointLevels& levels, const ContentDensityOptions& options)
    : levels_(levels), options_(options), tiles_per_level_(PointLevels::kLevels, 0) {
  options_.tile_px = std::max(1, options_.tile_px);
  if (std::has_single_bit(unsigned(options_.tile_px))) tile_shift_ = std::countr_zero(unsigned(options_.tile_px));
}

ContentDensity::LevelRange ContentDensity::levels_under(glm::vec2 min_px, glm::vec2 max_px) const {
  if (!active_) return {PointLevels::kFinest, PointLevels::kFinest};
  LevelRange range{PointLevels::kFinest, 0};
  const int x0 = tile_column(min_px.x), x1 = tile_column(max_px.x);
  for (int y = tile_row(min_px.y), y1 = tile_row(max_px.y); y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const std::uint8_t level = tile_level_[std::size_t(y) * std::size_t(tiles_x_) + std::size_t(x)];
      range.lowest = std::min(range.lowest, level);
      range.highest = std::max(range.highest, level);
    }
  return range;
}

void ContentDensity::begin_frame(const GazeMapping& mapping, unsigned workers) {
  const int tiles_x = (mapping.screen_width_px + options_.tile_px - 1) / options_.tile_px;
  const int tiles_y = (mapping.screen_height_px + options_.tile_px - 1) / options_.tile_px;
  if (tiles_x != tiles_x_ || tiles_y != tiles_y_) {
    tiles_x_ = std::max(1, tiles_x), tiles_y_ = std::max(1, tiles_y);
    have_contrast_ = false;
  }
  const std::size_t tiles = std::size_t(tiles_x_) * std::size_t(tiles_y_);
  active_ = enabled() && have_contrast_;
  std::fill(tiles_per_level_.begin(), tiles_per_level_.end(), 0u);
  if (!active_) tiles_per_level_[PointLevels::kFinest] = std::uint32_t(tiles);
  if (!enabled()) return;
  if (active_) levels_from_ranges();
  worker_range_.resize(workers);
  for (auto& range : worker_range_) range.assign(tiles, glm::vec2(INFINITY, -INFINITY));
}

void ContentDensity::end_frame(bool ok) {
  if (!enabled()) return;
  have_contrast_ = ok;
  if (!ok || worker_range_.empty()) return;
  for (std::size_t w = 1; w < worker_range_.size(); ++w)  // reduce into worker 0's ranges
    for (std::size_t t = 0; t < worker_range_[0].size(); ++t) {
      worker_range_[0][t].x = std::min(worker_range_[0][t].x, worker_range_[w][t].x);
      worker_range_[0][t].y = std::max(worker_range_[0][t].y, worker_range_[w][t].y);
    }
}

// Each tile's level from the contrast of its 3x3 neighbourhood's luminance range: an
// edge on a tile's border, or in the tile beside it, keeps the tile's density.
void ContentDensity::levels_from_ranges() {
  const std::vector<glm::vec2>& range = worker_range_[0];
  tile_level_.assign(range.size(), 0);
  tile_contrast_.assign(range.size(), 0.0f);
  for (int y = 0; y < tiles_y_; ++y)
    for (int x = 0; x < tiles_x_; ++x) {
      glm::vec2 around(INFINITY, -INFINITY);
      for (int ny = std::max(0, y - 1); ny <= std::min(tiles_y_ - 1, y + 1); ++ny)
        for (int nx = std::max(0, x - 1); nx <= std::min(tiles_x_ - 1, x + 1); ++nx) {
          const glm::vec2 r = range[std::size_t(ny) * std::size_t(tiles_x_) + std::size_t(nx)];
          around = glm::vec2(std::min(around.x, r.x), std::max(around.y, r.y));
        }
      const float contrast = tile_contrast(around.x, around.y, options_.dark_luminance);
      const std::uint8_t level = level_for_contrast(contrast, options_);
      tile_level_[std::size_t(y) * std::size_t(tiles_x_) + std::size_t(x)] = level;
      tile_contrast_[std::size_t(y) * std::size_t(tiles_x_) + std::size_t(x)] = contrast;
      ++tiles_per_level_[level];
    }
}

}  // namespace foveart::foveation
