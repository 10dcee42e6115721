// The settings `fovea-eval pricelist` sweeps: the full render at 1..16 rays per
// pixel (the baseline), the full render with the foveated frames' image history
// at each history ray count, foveated frames over interpolation x k x density
// scale x rays per point x fovea pattern, with and without the image history, and
// the content-aware family beside them: the same frames (without history) at each
// content contrast, and at each contrast of rays per point by content.
#pragma once

#include <string>
#include <vector>

namespace foveart::eval {

struct PriceSetting {
  bool full = false;                      // the full render instead of a foveated frame
  int rays_per_point = 1;                 // a full render's points are its pixels
  std::string interpolation = "nearest";  // nearest | msm | rbf
  int k = 1;
  double density_scale = 1.0;
  std::string pattern = "pixel-grid";  // pixel-grid | thesis
  // Content-aware density (foveation/content_density.hpp): a tile's contrast for all its
  // points; 0: density by eccentricity alone.
  double content_contrast = 0.0;
  // Rays per point by content (foveation/point_rays.hpp): the tile contrast from which a point
  // casts all its rays; 0: every point casts rays_per_point.
  double content_rays = 0.0;
  // The product's image history (TemporalMode::image) over a sequence of frames of
  // new jitter, full or foveated; without it, one frame of one jitter seed.
  bool history = false;

  // Stable name, e.g. "full_spp4", "full_spp1_image", "nearest_k1_s1_pixel-grid_r1", "msm_k5_s2_thesis_r4_image",
  // "msm_k5_s1_pixel-grid_r1_c0.5" (content-aware density), "msm_k5_s1_pixel-grid_r4_cr0.5" (rays
  // per point by content).
  std::string id() const;
  // The settings that share one set of tables (point set, neighbours, weights).
  std::string table_id() const;
};

// Each list is the `fovea-eval pricelist` option of the same name (kebab-case).
struct PriceGrid {
  std::vector<int> full_rays_per_point = {1, 2, 4, 8, 16};
  std::vector<std::string> interpolation = {"nearest:1", "msm:5", "msm:10", "rbf:5", "rbf:10"};  // method:k
  std::vector<double> density_scale = {1.0, 1.5, 2.0};
  std::vector<int> rays_per_point = {1, 2, 4, 8};
  std::vector<std::string> pattern = {"pixel-grid", "thesis"};
  // Content contrasts of the content-aware rows (_c suffix), each at every interpolation, scale,
  // pattern and rays per point, without history; a 0 is skipped (the eccentricity-only rows are
  // always measured, for comparison).
  std::vector<double> content_contrast = {0.25, 0.5, 1.0};
  // Contrasts of the rows whose rays per point follow the content (_cr suffix), as the
  // content-aware rows but only at more than 1 ray per point (at 1 they trace the same rays).
  std::vector<double> content_rays = {0.5};
  // Rays per point (and per pixel: full_sppN_image) measured with the image history too.
  std::vector<int> history_rays_per_point = {1};
};

// The small grid of --quick: full render at 1-8 rays per pixel; nearest and MSM k=5 at
// scale 1 and 2, both patterns, 1 and 4 rays, the image history at 1 (full_spp1_image too);
// content-aware rows at contrast 0.5 and rays per point by content at 0.5.
PriceGrid quick_grid();

// Every setting of a grid, the full-render baseline first (full_sppN, then
// full_sppN_image for each history ray count); false and *error
// naming the bad entry ("interpolation 'foo'", "k 0").
[[nodiscard]] bool expand_grid(const PriceGrid& grid, std::vector<PriceSetting>* out, std::string* error);

// "a,b,c" -> items; false when an item is empty.
[[nodiscard]] bool split_list(const std::string& text, std::vector<std::string>* out);

}  // namespace foveart::eval
