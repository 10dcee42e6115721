#include "foveation/ray_history.hpp"

#include <algorithm>
#include <cmath>

namespace foveart::foveation {

RayHistory::RayHistory(const ViewTables& tables, const TemporalOptions& blend, const RayHistoryOptions& options)
    : tables_(tables),
      options_(options),
      restarts_(blend),
      cache_(RayCacheOptions{options.pixel_filter, true, options.max_age_frames}) {}

void RayHistory::forget() {
  restarts_.reset();
  cache_.clear();
  last_view_.reset();
}

TemporalFrame RayHistory::begin(const FrameContext& frame) {
  const bool history_empty = !last_view_;  // the first frame, or the one after a failed frame
  const GazeMapping& m = frame.mapping;
  TemporalFrame t;
  t.kept = true;
  t.reset = restarts_.begin_frame(m.screen_width_px, m.screen_height_px, m.gaze_px, frame.restart);
  t.blend = restarts_.options();
  t.blend.current_weight = restarts_.frame_weight();
  t.rays = true;
  t.ray_restart = history_empty || (t.reset && !options_.keep_through_restarts);
  t.ray_filter = options_.pixel_filter;
  t.ray_max_age_frames = options_.max_age_frames;
  t.ray_pixels = &pixel_;
  return t;
}

TemporalFrame RayHistory::decide(const FrameContext& frame, const TracedPoints& traced, Executor& executor) {
  TemporalFrame t = begin(frame);
  if (traced.colors.rgba.empty()) {  // traced elsewhere (FoveatedView::plan): the device makes the pixels itself
    t.ray_pixels = nullptr;
  } else {
    prepare_pixels(frame, traced, true, executor);  // what the cache elsewhere takes
  }
  last_view_ = frame.view;
  return t;
}

bool RayHistory::apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources,
                       Executor& executor, TemporalFrame* decision, std::string* error) {
  HostFrame* host = host_frame(resources, "the CPU's ray history", error);
  if (host == nullptr) return false;
  const ImageRgb& reconstructed = host->reconstructed;
  *decision = begin(frame);
  filter(frame, traced, decision->ray_restart, executor);
  // Every pixel a ray of the cache reaches shows the cache; any other the reconstruction.
  const int w = int(frame.view.width_px), h = int(frame.view.height_px);
  executor.parallel_for(std::size_t(h), [&](std::size_t y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t p = y * std::size_t(w) + std::size_t(x);
      if (weight_[p] > 0.0f) continue;
      const float* from = reconstructed.at(x, int(y));
      float* to = image_.at(x, int(y));
      for (int c = 0; c < 3; ++c) to[c] = from[c];
    }
  });
  last_view_ = frame.view;
  host->output = &image_;
  return true;
}

void RayHistory::filter(const FrameContext& frame, const TracedPoints& traced, bool restart, Executor& executor) {
  const auto& runs = traced.rays;
  if (restart) cache_.clear();
  cache_.begin_frame(frame.view, executor);
  std::vector<std::size_t>& first = run_first_ray_;  // a run's rays, in run order
  first.assign(runs.size() + 1, 0);
  for (std::size_t r = 0; r < runs.size(); ++r) first[r + 1] = first[r] + runs[r].size();
  const std::size_t base = cache_.add_rays(first.back());
  executor.parallel_for(runs.size(), [&](std::size_t r) {
    for (std::size_t i = 0; i < runs[r].size(); ++i) {
      const TracedRay& ray = runs[r][i];
      cache_.set_ray(base + first[r] + i, ray.sample_px, ray.rgb, ray.depth_m, ray.pixel);
    }
  });
  prepare_pixels(frame, traced, false, executor);

  // The periphery's depth test, where this frame has no ray per pixel (the
  // pixel grid's runs inside the cache).
  const int w = int(frame.view.width_px), h = int(frame.view.height_px);
  executor.parallel_chunks(cache_.kept(), 4096, [&](std::size_t first_ray, std::size_t last_ray, unsigned) {
    for (std::size_t i = first_ray; i < last_ray; ++i) {
      const glm::vec2 q = cache_.kept_sample_px(i);
      if (!cache_.kept_on_screen(i) || !(q.x >= 0.0f && q.y >= 0.0f && q.x < float(w) && q.y < float(h))) continue;
      const std::size_t p = std::size_t(q.y) * std::size_t(w) + std::size_t(q.x);
      if (grid_pixel_[p] != 0) continue;
      const float farthest_new_m = pixel_[p].y;
      if (farthest_new_m >= 0.0f && std::isfinite(farthest_new_m) &&
          kept_ray_covered(cache_.distance_m(i), farthest_new_m))
        cache_.forget(i);
    }
  });

  // Beyond the pixel grid, each pixel filters the rays around it with the
  // pixel filter widened to the disc of its nearest point, so that it spreads
  // a ray as far as the disc spreads the point's rays (disc_footprint_px):
  // where rays are sparse the pixels blur as much as the points' own discs
  // do, but from every ray kept there, each where its surface now is.
  periphery_pixels_.clear();
  periphery_centre_px_.clear();
  periphery_footprint_px_.clear();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
      const float footprint_px = pixel_[p].x;
      if (footprint_px <= 1.0f) continue;  // the pixel filter itself (resolve)
      periphery_pixels_.push_back(std::uint32_t(p));
      periphery_centre_px_.emplace_back(float(x) + 0.5f, float(y) + 0.5f);
      periphery_footprint_px_.push_back(footprint_px);
    }
  cache_.filter_at(periphery_centre_px_, periphery_footprint_px_, executor, &periphery_rgb_, &periphery_weight_);

  // Every pixel with the pixel filter itself, then the wider filters' pixels over them.
  cache_.resolve(executor, &image_, &weight_);
  executor.parallel_chunks(periphery_pixels_.size(), 4096, [&](std::size_t first_pixel, std::size_t last_pixel,
                                                                 unsigned) {
    for (std::size_t j = first_pixel; j < last_pixel; ++j) {
      const std::size_t p = periphery_pixels_[j];
      weight_[p] = periphery_weight_[j];
      if (periphery_weight_[j] <= 0.0f) continue;
      float* to = image_.rgb.data() + 3 * p;
      for (int c = 0; c < 3; ++c) to[c] = periphery_rgb_[j][c];
    }
  });
}

void RayHistory::prepare_pixels(const FrameContext& frame, const TracedPoints& traced, bool grid_depth_test,
                                Executor& executor) {
  const PointSet& points = tables_.points;
  const NeighborTable& nt = tables_.neighbors;
  const GazeMapping& mapping = frame.mapping;
  const int w = mapping.screen_width_px, h = mapping.screen_height_px;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  grid_pixel_.assign(pixels, 0);
  if (grid_depth_test) drawn_farthest_m_.assign(pixels, -1.0f);
  executor.parallel_for(traced.rays.size(), [&](std::size_t r) {  // a pixel-grid point is in one run only
    for (const TracedRay& ray : traced.rays[r]) {
      if (ray.pixel.x < 0 || ray.pixel.y < 0 || ray.pixel.x >= w || ray.pixel.y >= h) continue;
      const std::size_t p = std::size_t(ray.pixel.y) * std::size_t(w) + std::size_t(ray.pixel.x);
      grid_pixel_[p] = 1;
      if (grid_depth_test) drawn_farthest_m_[p] = std::max(drawn_farthest_m_[p], traced_distance_m(ray.depth_m));
    }
  });
  if (grid_depth_test) farthest_around_3x3(drawn_farthest_m_, w, h, executor, &around_farthest_m_);

  // A pixel-grid pixel: the pixel filter, and the 3x3 test. Beyond the grid:
  // the nearest point's disc footprint, and the farthest new ray of the
  // traced points among the k nearest (the 3x3 test's counterpart where this
  // frame has no ray per pixel; a missed or depthless one among them, or
  // none traced, cannot tell; a point content density filled has no ray).
  pixel_.resize(pixels);
  executor.parallel_for(std::size_t(h), [&](std::size_t y) {
    for (std::size_t x = 0; x < std::size_t(w); ++x) {
      const std::size_t p = y * std::size_t(w) + x;
      if (grid_pixel_[p] != 0) {
        pixel_[p] = glm::vec2(1.0f, grid_depth_test ? around_farthest_m_[p] : NAN);
        continue;
      }
      const std::size_t canvas = mapping.canvas_index(x, y, std::size_t(nt.width_px()));
      const float footprint_px = disc_footprint_px(options_.pixel_filter, points.radius_px[nt.neighbor(canvas, 0)]);
      float farthest_new_m = -1.0f;
      for (int j = 0; j < nt.k(); ++j) {
        const std::uint32_t n = nt.neighbor(canvas, j);
        if (traced.colors.rgba[n].a == 0.0f) continue;
        const float d = traced.farthest_m[n];
        farthest_new_m = std::isnan(d) ? INFINITY : std::max(farthest_new_m, d);
      }
      pixel_[p] = glm::vec2(std::max(footprint_px, 1.0f), farthest_new_m);
    }
  });
}

}  // namespace foveart::foveation
