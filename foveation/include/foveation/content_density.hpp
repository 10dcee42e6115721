// Density that follows the content (thesis 8.2; docs/content_density.md): each screen tile traces
// the points of the levels (point_levels.hpp) its visible contrast calls for, measured from the
// colours the points had in the last frame. A tile whose luminance range is flat or dark traces
// level 0 only (about a ninth of its Poisson points), finer levels as its contrast rises, a high-
// contrast one all. A tile's contrast is that of its 3x3 neighbourhood, so an edge keeps its
// density on both sides, on a tile's border too. The first frame, the one after a failed frame
// and the first at a new screen size trace every point. A saccade or a head move keeps them: the
// tiles' contrast is the last frame's where its points fell on the screen (the 3x3 neighbourhood
// covers a move of less than a tile). The same contrast sets how many rays a point casts
// (ContentDensityOptions::rays_contrast, point_rays.hpp), with or without the thinning.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/gather.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/point_levels.hpp"
#include "foveation/srgb.hpp"
#include "foveation/temporal_mode.hpp"

namespace foveart::foveation {

struct ContentDensityOptions {
  // Contrast (below) at which a tile traces all its points; from half of it, level 2
  // (about half of them), from a quarter, level 1 (a quarter). 0: off, every visible
  // point is traced.
  float full_contrast = 0.0f;
  // Luminance (display-linear, 1 = white) added to both ends of the range: below it
  // the eye's sensitivity falls (the de Vries-Rose range), so dark tiles read as flat.
  float dark_luminance = 0.01f;
  float exposure = 1.0f;  // radiance to display-linear
  int tile_px = 16;
  // Rays per point by the tile's contrast and the point's disc (point_ray_count,
  // point_rays.hpp): the contrast from which a point casts all its rays. 0: off, every
  // point casts rays_per_point.
  float rays_contrast = 0.0f;
  // Eccentricity (degrees) over which rays_contrast doubles, in steps: a point from 1, 2, 3,
  // 4 times this away from the gaze casts all its rays from 2, 4, 8, 16 times rays_contrast
  // (rays_contrast_steps, point_rays.hpp). 0: the same contrast everywhere.
  float rays_doubling_ecc_deg = 0.0f;
  bool thins() const { return full_contrast > 0.0f; }
  bool varies_rays() const { return rays_contrast > 0.0f; }
  bool enabled() const { return thins() || varies_rays(); }
};

// The largest rays_doubling_ecc_deg: a step at 90 degrees or beyond is never reached.
inline constexpr double kMaxRaysDoublingEccDeg = 90.0;
inline bool valid_rays_doubling_ecc_deg(double deg) {
  return deg >= 0.0 && deg <= kMaxRaysDoublingEccDeg;
}

// The product's rays per point by contrast where the user names none (docs/content_density.md,
// "Defaults"): all of them from this tile contrast, where a point casts several rays and the
// density is the thesis's or sparser. With one ray per point there is nothing to vary; at a
// denser scale, Poisson discs under a pixel cast fewer rays and the perceptual metric sees it.
inline constexpr float kDefaultRaysContrast = 0.5f;
inline float default_rays_contrast(int rays_per_point, double density_scale) {
  return rays_per_point > 1 && density_scale >= 1.0 ? kDefaultRaysContrast : 0.0f;
}

// The product's doubling of that contrast with eccentricity where the user names none (docs/
// content_density.md, "By eccentricity"): every 30 degrees where the history keeps the traced rays (the
// render cache), whose flicker it leaves as it was; off with the image history, whose outer
// rings flicker more where points cast fewer rays, and with no history.
inline constexpr float kDefaultRaysDoublingEccDeg = 30.0f;
inline float default_rays_doubling_ecc_deg(TemporalMode temporal) {
  return temporal == TemporalMode::rays ? kDefaultRaysDoublingEccDeg : 0.0f;
}

// Michelson contrast of a tile's luminance range with the dark floor (Peli 1990's band
// contrast's simplest form): (max - min) / (max + min + 2 dark).
float tile_contrast(float min_luminance, float max_luminance, float dark_luminance);

// The level a tile of that contrast traces.
std::uint8_t level_for_contrast(float contrast, const ContentDensityOptions& options);

class ContentDensity {
 public:
  ContentDensity(const PointLevels& levels, const ContentDensityOptions& options);

  bool enabled() const { return options_.enabled(); }
  // A frame at `mapping` begins: its tiles' levels from the last frame's colours.
  void begin_frame(const GazeMapping& mapping, unsigned workers);
  // This frame traces the point at screen_px (else it is filled from its parents).
  bool traces(std::uint32_t point, glm::vec2 screen_px) const {
    return !active_ || levels_.level[point] <= tile_level_[tile_of(screen_px)];
  }
  // The lowest and highest level of the tiles under a screen box: a point of a level at
  // or below the lowest is traced, one above the highest is not, without its tile. Both
  // kFinest while the frame does not thin.
  struct LevelRange {
    std::uint8_t lowest, highest;
  };
  LevelRange levels_under(glm::vec2 min_px, glm::vec2 max_px) const;
  // The contrast of the tile at screen_px (its 3x3 neighbourhood's, last frame's); +inf
  // while none is measured (the first frame, after a failed one): every ray is cast.
  float contrast(glm::vec2 screen_px) const {
    return active_ ? tile_contrast_[tile_of(screen_px)] : INFINITY;
  }
  // A point's colour this frame, for the next frame's contrast (worker: the executor's slot).
  void observe(unsigned worker, glm::vec2 screen_px, const Rgba& colour) {
    const float l = rec709_luminance(colour.r, colour.g, colour.b) * options_.exposure;
    glm::vec2& range = worker_range_[worker][tile_of(screen_px)];
    range.x = std::min(range.x, l);
    range.y = std::max(range.y, l);
  }
  // The frame ends: ok, its observations give the next frame's levels; else the next
  // frame traces every point.
  void end_frame(bool ok);

  const ContentDensityOptions& options() const { return options_; }
  const PointLevels& levels() const { return levels_; }
  // Tiles of the frame per level (0..kFinest), for the stats.
  const std::vector<std::uint32_t>& tiles_per_level() const { return tiles_per_level_; }

 private:
  // Points in the visible margin count in the nearest tile.
  int tile_column(float x_px) const { return std::clamp(tile_index(floor_px(x_px)), 0, tiles_x_ - 1); }
  int tile_row(float y_px) const { return std::clamp(tile_index(floor_px(y_px)), 0, tiles_y_ - 1); }
  // floor() of a screen coordinate, inline (without SSE4.1 std::floor is a call per point).
  static int floor_px(float x_px) {
    const int i = int(x_px);
    return float(i) > x_px ? i - 1 : i;
  }
  // A pixel coordinate's tile: a shift for a power-of-two tile (the default 16 px); the
  // same index for every pixel >= 0, and a negative one clamps to 0 either way.
  int tile_index(int px) const { return tile_shift_ >= 0 ? px >> tile_shift_ : px / options_.tile_px; }
  std::size_t tile_of(glm::vec2 screen_px) const {
    return std::size_t(tile_row(screen_px.y)) * std::size_t(tiles_x_) + std::size_t(tile_column(screen_px.x));
  }
  void levels_from_ranges();

  const PointLevels& levels_;
  ContentDensityOptions options_;
  int tiles_x_ = 0, tiles_y_ = 0;
  int tile_shift_ = -1;         // log2(tile_px) when a power of two, else -1
  bool active_ = false;         // this frame thins
  bool have_contrast_ = false;  // the last frame's observations hold
  std::vector<std::uint8_t> tile_level_;
  std::vector<float> tile_contrast_;
  std::vector<std::vector<glm::vec2>> worker_range_;  // per worker, per tile: min, max luminance
  std::vector<std::uint32_t> tiles_per_level_;
};

}  // namespace foveart::foveation
