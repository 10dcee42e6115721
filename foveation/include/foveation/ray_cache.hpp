// A history of traced rays, anchored in the world (a render cache, Walter et
// al. 1999): every ray keeps where it hit (a point on a surface, or a
// direction for a miss or an engine without depth) and the colour it was
// traced with. Every frame each kept ray is projected into the new view and
// filtered, with this frame's new rays, into the pixels around it with the
// pixel filter's weights (a ratio estimator, pbrt-v4 8.8). A kept ray is
// forgotten once a nearer surface covers it (its depth test), once it falls
// beyond the filter's reach of the image, or once it is older than the
// cache's age limit.
//
// Unlike a history image warped every frame, nothing is resampled: a kept ray
// lands where its surface now is, so the history neither blurs nor drifts,
// and its rays are not lost when the gaze jumps (docs/foveation.md, "A history of rays:
// the render cache").
//
// filter_at filters the same rays at any centre with the pixel filter
// widened to a footprint: beyond the pixel grid, where rays are sparser than
// pixels, each pixel filters them as widely as its nearest point's disc.
//
// A frame, on one thread at a time (its work spread over the executor):
//   begin_frame(view)  ->  [kept_* / set_kept_rgb]  ->  add_rays / set_ray  ->  [forget / filter_at]
//     ->  resolve(out) or abandon_frame()
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "foveation/executor.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/image.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/shader_constants.h"
#include "foveation/ray_trace.h"

namespace foveart::foveation {

// How much farther than the new rays around it a kept hit may lie and still
// count as seen: the new rays cross its pixels elsewhere, so a slanted
// surface's depth differs a little across them.
inline constexpr float kKeptRayOcclusionTolerance = static_cast<float>(FOVEART_KEPT_RAY_OCCLUSION_TOLERANCE);

// The render cache's depth test for one kept ray, given the farthest (finite)
// of the new rays around it: covered when it lies farther than they do, by
// more than the tolerance; a kept miss (+inf) is covered wherever they all hit.
inline bool kept_ray_covered(float kept_distance_m, float farthest_new_m) {
  return kept_distance_m > farthest_new_m * (1.0f + kKeptRayOcclusionTolerance);
}

// The pixel filter's weight of a ray `offset_px` from a pixel's centre, per
// axis: box 1 inside the pixel ([-0.5, 0.5), as floor() assigns rays to
// pixels); bspline2 the quadratic B-spline, box * box * box on (-1.5, 1.5) (Unser 1999).
inline float pixel_filter_weight(PixelFilter filter, float offset_px) {
  if (filter == PixelFilter::box) return offset_px >= -0.5f && offset_px < 0.5f ? 1.0f : 0.0f;
  const float u = offset_px < 0.0f ? -offset_px : offset_px;
  if (u < 0.5f) return 0.75f - u * u;
  if (u < 1.5f) return 0.5f * (1.5f - u) * (1.5f - u);
  return 0.0f;
}

// The bspline2 weights of a ray t_px (in [-0.5, 0.5)) from the centre of its
// own pixel, for the pixels before it, its own and the one after:
// pixel_filter_weight at offsets t + 1, t and t - 1, without a branch.
inline void bspline2_weights(float t_px, float out_weights[3]) {
  out_weights[0] = 0.5f * (0.5f - t_px) * (0.5f - t_px);
  out_weights[1] = 0.75f - t_px * t_px;
  out_weights[2] = 0.5f * (0.5f + t_px) * (0.5f + t_px);
}

// The footprint (RayCache::filter_at) at which the pixel filter spreads a
// ray as widely as a disc of radius_px spreads its point's rays (thesis 4.2):
// the same per-axis variance, r^2 / 4 (box f^2 / 12, bspline2 f^2 / 4).
inline float disc_footprint_px(PixelFilter filter, float radius_px) {
  return filter == PixelFilter::box ? 1.7320508f * radius_px : radius_px;
}

// The cell grid filter_at bins rays in (cache_filter.comp's too): cells of
// FOVEART_RAY_CACHE_CELL_PX, the first one cell before the image, so that the
// grid holds every ray within the filter's reach (at most 1 px beyond the image).
inline glm::ivec2 ray_cache_cell(glm::vec2 sample_px) {
  return glm::ivec2(glm::floor(sample_px / float(FOVEART_RAY_CACHE_CELL_PX))) + 1;
}

// The cells that hold every ray of a filter window [centre - r, centre + r)
// per axis, before clamping to the grid. The window is half-open, so its last
// cell is the one before the cell that starts at its end: at footprint 1,
// every pixel reads 2 cells per axis (bspline2) or 1 (box), never a third.
struct CellRange {
  glm::ivec2 first, last;
};
inline CellRange filter_window_cells(glm::vec2 centre_px, float r_px) {
  return {ray_cache_cell(centre_px - r_px),
          glm::ivec2(glm::ceil((centre_px + r_px) / float(FOVEART_RAY_CACHE_CELL_PX)))};
}

// One ray a frame traced, as the render cache takes it (RayCache::set_ray).
struct TracedRay {
  glm::vec2 sample_px;
  glm::vec3 rgb;
  float depth_m;     // the engine's hit distance (+inf: a miss; NaN: none)
  glm::ivec2 pixel;  // the pixel it was drawn for, which the depth test compares kept rays with; -1: none
};

// A new ray's distance from the eye for the depth test: its depth, or +inf
// for a miss or no depth (a direction).
inline float traced_distance_m(float depth_m) { return std::isfinite(depth_m) && depth_m >= 0.0f ? depth_m : INFINITY; }

// The render cache's depth test's reach on the pixel grid (Walter et al.
// 1999): from the farthest new ray drawn for each pixel (< 0: none), the
// farthest over the 3x3 pixels around each (+inf: one of them has none).
void farthest_around_3x3(const std::vector<float>& farthest_drawn_m, int width_px, int height_px, Executor& executor,
                         std::vector<float>* out_m);

struct RayCacheOptions {
  PixelFilter filter = PixelFilter::box;
  // Forget a kept ray that a nearer surface covers (the render cache's depth
  // test). Off only for a history whose kept rays are traced again each frame.
  bool forget_covered = true;
  // Forget a kept ray this many frames after it was traced (0: never). Bounds
  // the rays kept, and so memory and filtering time, on a still view.
  std::uint32_t max_age_frames = 0;
};

class RayCache {
 public:
  explicit RayCache(const RayCacheOptions& options = {}) : options_(options) {}

  const RayCacheOptions& options() const { return options_; }
  // Forgets every kept ray (a restart).
  void clear() { anchors_.clear(); }
  // Rays kept after the last resolve().
  std::size_t size() const { return anchors_.size(); }

  // Projects every kept ray into `view`: where it falls, and whether it is
  // within the filter's reach of the image.
  void begin_frame(const FoveartEyeView& view, Executor& executor);

  // After begin_frame, kept ray i (i < kept()): where it falls in this view,
  // whether within reach, and its colour, which a caller tracing it again may replace.
  std::size_t kept() const { return kept_; }
  glm::vec2 kept_sample_px(std::size_t i) const { return sample_px_[i]; }
  bool kept_on_screen(std::size_t i) const { return row_[i] >= 0; }
  void set_kept_rgb(std::size_t i, glm::vec3 rgb) { anchors_[i].rgb = rgb; }
  // Ray i's distance from this view's eye, kept or new (+inf: a miss or no depth, a direction).
  float distance_m(std::size_t i) const;
  // Forgets kept ray i this frame: a caller's own depth test where this frame
  // has no ray per pixel (the Poisson periphery), before filter_at and resolve.
  void forget(std::size_t i) { row_[i] = -1; }

  // Makes room for n new rays of this frame (traced from this view's eye) and
  // returns the first one's index for set_ray; set_ray may then run from
  // several threads, each on its own indices.
  std::size_t add_rays(std::size_t n);
  // New ray i: where it crossed the screen, its colour, its hit distance
  // (+inf: a miss; NaN: no depth) and the pixel it was drawn for, which the
  // depth test compares kept rays with (a pixel filter's jitter may carry the
  // ray into a neighbour; without it, the pixel it crossed). One beyond the
  // filter's reach of the image is not filtered and not kept.
  void set_ray(std::size_t i, glm::vec2 sample_px, glm::vec3 rgb, float depth_m, glm::ivec2 drawn_pixel);
  void set_ray(std::size_t i, glm::vec2 sample_px, glm::vec3 rgb, float depth_m) {
    set_ray(i, sample_px, rgb, depth_m, glm::ivec2(glm::floor(sample_px)));
  }

  // After the new rays: filters every ray within reach into point j at
  // centres_px[j] (screen pixels) with the pixel filter scaled by
  // footprint_px[j] per axis (1: a pixel's own), as resolve does for a pixel
  // centre. Writes out_rgb[j] = sum(w L) / sum(w) and out_weight[j] = sum(w)
  // (0: no ray reaches it, out_rgb[j] untouched); both sized to the centres.
  // Forgets the covered kept rays first, as resolve does.
  void filter_at(const std::vector<glm::vec2>& centres_px, const std::vector<float>& footprint_px,
                 Executor& executor, std::vector<glm::vec3>* out_rgb, std::vector<float>* out_weight);

  // Forgets the covered kept rays (RayCacheOptions::forget_covered), filters
  // every ray within reach into *out_linear (resized to the view) and its
  // weight sum per pixel into *out_weight (0: no ray reaches the pixel; may be
  // null), then keeps the rays still within reach and young enough.
  void resolve(Executor& executor, ImageRgb* out_linear, std::vector<float>* out_weight = nullptr);
  // Ends a frame that failed instead: its new rays are dropped, the kept ones stay as they were.
  void abandon_frame() {
    anchors_.resize(kept_);
    kept_ = 0;
  }

 private:
  struct Anchor {
    glm::vec3 point_m_or_direction{0.0f};
    glm::vec3 rgb{0.0f};
    std::uint32_t age_frames = 0;  // frames since it was traced
    bool at_infinity = false;      // a miss or no depth: a direction, not a point
  };
  void forget_covered(Executor& executor);
  void forget_covered_once(Executor& executor) {
    if (options_.forget_covered && kept_ > 0 && !covered_forgotten_) forget_covered(executor);
    covered_forgotten_ = true;
  }
  // A ray at q: its pixel row + the filter's reach, or -1 beyond the filter's reach of the image.
  int row_within_reach(glm::vec2 q) const;
  // The steps of resolve: the rays sorted by row, the filter over them, the rays kept for the next frame.
  void sort_by_row(Executor& executor);
  void filter_rows(Executor& executor, ImageRgb* out_linear, std::vector<float>* out_weight) const;
  void keep_young_rays();

  RayCacheOptions options_;
  std::vector<Anchor> anchors_;  // the kept rays, then (during a frame) this frame's new ones
  std::size_t kept_ = 0;
  bool covered_forgotten_ = false;  // this frame's depth test has run
  int width_px_ = 0, height_px_ = 0;
  EyeFrustum frustum_{};
  EyePose pose_{};
  // Per ray of this frame (the kept ones, then the new ones):
  std::vector<glm::vec2> sample_px_;  // where it falls now
  std::vector<std::int32_t> row_;     // its pixel row + the filter's reach; -1: beyond reach or forgotten
  std::vector<std::int32_t> drawn_pixel_;  // per new ray (index - kept_): its pixel's index, -1 off the image
  // Per pixel: the farthest of this frame's new rays drawn for it (+inf: one missed; < 0: none), then
  // the farthest over the 3x3 pixels around it (+inf: one of them unknown).
  std::vector<float> new_depth_m_, around_depth_m_;
  // The counting sort by row, per chunk of rays: chunk_rows_[c * rows + r] is
  // first how many of chunk c fall in row r, then where they go in by_row_.
  std::vector<std::uint32_t> chunk_rows_;
  struct Sample {  // a within-reach ray as the filter reads it
    glm::vec3 rgb;
    std::int32_t x_px;  // its pixel column
    glm::vec2 t_px;     // from its pixel's centre, in [-0.5, 0.5)
  };
  std::vector<Sample> by_row_;            // within-reach rays ordered by their pixel row
  std::vector<std::uint32_t> row_begin_;  // by_row_[row_begin_[y], row_begin_[y + 1]): row y's
  // filter_at's rays by cell of a coarse grid, as by_row_ by row: cell c's are
  // by_cell_[cell_begin_[c], cell_begin_[c + 1]), only in cells a centre reaches.
  struct CellSample {
    glm::vec2 sample_px;
    glm::vec3 rgb;
  };
  std::vector<std::int32_t> cell_;  // per ray: its cell, -1 none reached
  std::vector<std::uint8_t> cell_needed_;
  std::vector<std::uint32_t> chunk_cells_, cell_begin_;
  std::vector<CellSample> by_cell_;
};

}  // namespace foveart::foveation
