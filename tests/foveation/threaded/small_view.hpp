// The small view the content-aware density tests frame (content_density_test.cpp,
// point_ray_count_test.cpp): a W x H eye of 60 deg across, its tables at a density scale,
// and a frame request with the gaze at its centre.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"

namespace foveart::foveation::small_view {

// The view's tables (point set, neighbours, weights) for `method` with k neighbours; a scale
// above 1 leaves the pixel grid's edge inside the view, so frames hold grid and Poisson points.
inline std::shared_ptr<const ViewTables> tables(std::uint32_t width_px, std::uint32_t height_px, double scale,
                                                std::uint64_t seed, InterpMethod method, int k) {
  PointSetKey key;
  key.display = DisplayModel::from_fov(width_px, height_px, 60.0);
  key.display.scale = scale;
  key.seed = seed;
  InterpOptions o;
  o.method = method;
  o.k = k;
  Executor executor(2);
  return load_view_tables(std::nullopt, key, o, executor);
}

// The view's tables at 64 pixels per degree and density scale 0.75: the pixel-exact fovea
// (DisplayModel::exact_fovea_radius_px) about 33 px in radius around the centre, and the
// grid margin the denser scale adds out to about 44 px.
inline std::shared_ptr<const ViewTables> grid_margin_tables(std::uint32_t width_px, std::uint32_t height_px,
                                                            InterpMethod method, int k) {
  PointSetKey key;
  key.display = DisplayModel::from_pixels_per_degree(int(width_px), int(height_px), 64.0);
  key.display.scale = 0.75;
  key.seed = 1;
  InterpOptions o;
  o.method = method;
  o.k = k;
  Executor executor(2);
  return load_view_tables(std::nullopt, key, o, executor);
}

// Frame `frame_index` of the view from 1.6 m, the gaze at its centre.
inline FrameRequest request(std::uint32_t width_px, std::uint32_t height_px, std::uint64_t frame_index) {
  FrameRequest r;
  EyePose pose;
  pose.position_m = {0.0f, 1.6f, 0.0f};
  r.view = make_eye_view(0, width_px, height_px, pose, -0.5f, 0.5f, 0.4f, -0.4f);
  r.frame_index = frame_index;
  r.gaze_px = {float(width_px) / 2.0f, float(height_px) / 2.0f};
  return r;
}

}  // namespace foveart::foveation::small_view
