#include "foveation/foveated_view.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>

#include <numbers>
#include <stdexcept>

#include "foveation/interpolation_cache.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/taa_reprojection.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::foveation {
namespace {

// Rays per engine callback call, and points of the set per parallel task: a
// task is a contiguous run of the Morton order (the rays of a packet are
// neighbours on the screen), small enough that the last task of a frame keeps
// the other threads idle only briefly.
constexpr std::uint32_t kBatchRays = 4096;
constexpr std::size_t kChunkPoints = 8192;
// Disc offsets are precomputed up to this many samples (64 MB); beyond, made per frame.
constexpr std::size_t kMaxPrecomputedSamples = std::size_t{8} << 20;

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

bool same_view(const FoveartEyeView& a, const FoveartEyeView& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

DisplayModel display_of_view(const FoveartEyeView& view) {
  const double span_rad = double(view.angle_right_rad) - double(view.angle_left_rad);
  return DisplayModel::from_fov(int(view.width_px), int(view.height_px), span_rad * 180.0 / std::numbers::pi);
}

int neighbor_count(const InterpOptions& interpolation) {
  return interpolation.method == InterpMethod::nn ? std::max(4, interpolation.k) : interpolation.k;
}

std::shared_ptr<const ViewTables> load_view_tables(const std::optional<std::filesystem::path>& cache_dir,
                                                   PointSetKey key, const InterpOptions& interpolation,
                                                   Executor& executor, std::optional<WeightPrecision> precision,
                                                   const ProgressFn& progress, const LogFn& log) {
  const auto t0 = Clock::now();
  // The point set and neighbour table are ~90% of a first build, the weights the rest.
  auto part = [&](double lo, double hi) -> ProgressFn {
    if (!progress) return {};
    return [=, &progress](double f) { progress(lo + (hi - lo) * f); };
  };
  key.k = neighbor_count(interpolation);
  auto out = std::make_shared<ViewTables>();
  out->key = key;
  FoveationTables tables = load_or_build_tables(cache_dir, key, executor, part(0.0, 0.9), log);
  out->points = std::move(tables.points);
  out->neighbors = std::move(tables.neighbors);
  CachedTable interp = load_or_build_interpolation_table(cache_dir, key, out->points, out->neighbors, interpolation,
                                                         executor, precision, part(0.9, 1.0), log);
  out->interpolation = std::move(interp.table);
  out->from_cache = tables.points_from_cache && tables.neighbors_from_cache && interp.from_cache;
  out->load_ms = ms_since(t0);
  return out;
}

FoveatedView::FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings)
    : tables_(std::move(tables)),
      settings_(settings),
      taa_(taa_options_for_rays(settings.taa_options, settings.rays_per_point)),
      ray_cache_(RayCacheOptions{settings.pixel_filter, true, settings.ray_cache_max_age_frames}),
      centre_(tables_ != nullptr ? settings.centre_deadband_deg * tables_->key.display.view_distance_px *
                                       std::numbers::pi / 180.0
                                 : 0.0) {
  if (tables_ == nullptr) throw std::invalid_argument("foveated view: no tables");
  if (settings_.rays_per_point < 1) throw std::invalid_argument("foveated view: rays per point must be >= 1");
  colors_.rgba.assign(tables_->points.size(), Rgba{});
  point_depth_m_.assign(tables_->points.size(), NAN);
  colors_.invalid = colors_.rgba.size();
  traced_.resize((tables_->points.size() + kChunkPoints - 1) / kChunkPoints);
  if (settings_.taa && settings_.taa_history == TaaHistory::ray_cache) {
    chunk_rays_.resize(traced_.size());
    point_farthest_m_.assign(tables_->points.size(), NAN);
  }
}

FrameResult FoveatedView::render(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                                 Executor& executor) {
  const PointSet& points = tables_->points;
  const DisplayModel& display = tables_->key.display;
  const FoveartEyeView& view = request.view;
  if (view.width_px != std::uint32_t(display.width_px) || view.height_px != std::uint32_t(display.height_px)) {
    throw std::invalid_argument("foveated view: a " + std::to_string(view.width_px) + "x" +
                                std::to_string(view.height_px) + " view for tables of a " +
                                std::to_string(display.width_px) + "x" + std::to_string(display.height_px) + " display");
  }
  if (trace_rays == nullptr) throw std::invalid_argument("foveated view: no ray-trace callback");
  FrameResult result;
  const auto t_frame = Clock::now();
  const glm::vec2 centre = centre_.update(request.gaze_px, request.saccade || request.blink);
  const GazeMapping mapping = map_gaze(int(view.width_px), int(view.height_px), centre);
  result.centre_px = mapping.gaze_px;
  const std::uint32_t spp = std::uint32_t(settings_.rays_per_point);
  const std::uint64_t seed = settings_.sample_seed + (settings_.new_jitter_each_frame ? request.frame_index : 0);

  // Disc offsets of a fixed seed are the same every frame: made once (a
  // pixel-grid point's jitter follows its screen pixel, so it is made per frame).
  const bool precomputed = !settings_.new_jitter_each_frame && points.size() * spp <= kMaxPrecomputedSamples;
  if (precomputed && (sample_offset_px_.empty() || sample_offset_seed_ != seed)) {
    sample_offset_px_.resize(points.size() * spp);
    executor.parallel_chunks(points.size(), 16384, [&](std::size_t first, std::size_t last, unsigned) {
      for (std::size_t i = first; i < last; ++i) {
        if (points.on_pixel_grid(i)) continue;
        for (std::uint32_t s = 0; s < spp; ++s)
          sample_offset_px_[i * spp + s] = unit_disc_sample(seed, std::uint32_t(i), int(s)) * points.radius_px[i];
      }
    });
    sample_offset_seed_ = seed;
  }
  const unsigned workers = executor.thread_count();
  const std::uint32_t batch_points = std::max<std::uint32_t>(1, kBatchRays / spp);
  if (batches_.size() < workers) {
    batches_.resize(workers);
    batch_points_.resize(workers);
  }
  result.select_ms = ms_since(t_frame);

  // Thesis 4.2, in one pass over chunks of the point set: each task forgets
  // the points it traced last frame, keeps the visible ones, casts spp rays
  // through each one's disc, hands them to the engine in batches and writes
  // each point's mean colour into its slot.
  const auto t_trace = Clock::now();
  const EyeFrustum frustum = eye_frustum(view);
  const EyePose pose = eye_pose(view);
  const VisibleRegion visible(mapping, points.visible_margin_px);
  std::atomic<std::uint64_t> traced_points{0}, failed_batches{0}, invalid_colours{0};
  std::atomic<bool> any_depth{false};
  const float inv_spp = 1.0f / float(spp);
  const bool keep_rays = !chunk_rays_.empty();  // TaaHistory::ray_cache
  executor.parallel_for(traced_.size(), [&](std::size_t chunk, unsigned worker) {
    std::vector<std::uint32_t>& traced = traced_[chunk];
    for (std::uint32_t id : traced) colors_.rgba[id] = Rgba{}, point_depth_m_[id] = NAN;
    traced.clear();
    if (keep_rays) chunk_rays_[chunk].clear();
    RayBatch& batch = batches_[worker];
    std::vector<std::uint32_t>& ids = batch_points_[worker];
    batch.resize(std::size_t(batch_points) * spp);
    ids.resize(batch_points);
    std::uint32_t n = 0;
    auto flush = [&] {
      const std::uint32_t rays = n * spp;
      if (batch.trace(trace_rays, user_data, view, request.frame_index, rays) != FOVEART_RESULT_SUCCESS) {
        failed_batches.fetch_add(1, std::memory_order_relaxed);
      } else if (const std::uint64_t bad = batch.invalid_components(rays); bad != 0) {
        invalid_colours.fetch_add(bad, std::memory_order_relaxed);
      } else {
        for (std::uint32_t j = 0, r = 0; j < n; ++j) {
          glm::vec3 sum(0.0f);
          float nearest_m = NAN;  // the point's depth: its nearest hit (NaN: the engine gave none)
          float farthest_m = 0.0f;  // its farthest (NaN: one gave none), for the ray cache's depth test
          // A pixel-grid ray is drawn for its point's pixel; a Poisson point's for none.
          const glm::ivec2 pixel = keep_rays && points.on_pixel_grid(ids[j])
                                       ? glm::ivec2(glm::floor(visible.to_screen(points.position_px[ids[j]])))
                                       : glm::ivec2(-1);
          for (std::uint32_t s = 0; s < spp; ++s, ++r) {
            sum += batch.rgb(r);
            const float d = batch.depth_m(r);
            if (d >= 0.0f && !(d >= nearest_m)) nearest_m = d;  // NaN and negative ignored
            farthest_m = d >= 0.0f ? std::max(farthest_m, d) : NAN;
            if (keep_rays) chunk_rays_[chunk].push_back(TracedRay{batch.sample_px(r), batch.rgb(r), d, pixel});
          }
          sum *= inv_spp;
          colors_.rgba[ids[j]] = Rgba{sum.x, sum.y, sum.z, 1.0f};
          point_depth_m_[ids[j]] = nearest_m;
          if (keep_rays) point_farthest_m_[ids[j]] = farthest_m;
          if (!std::isnan(nearest_m)) any_depth.store(true, std::memory_order_relaxed);
          traced.push_back(ids[j]);
        }
      }
      n = 0;
    };
    const std::size_t last = std::min(points.size(), (chunk + 1) * kChunkPoints);
    std::uint64_t chunk_points = 0;
    for (std::size_t i = chunk * kChunkPoints; i < last; ++i) {
      const glm::vec2 screen = visible.to_screen(points.position_px[i]);
      if (!visible.contains(screen)) continue;
      const std::uint32_t id = std::uint32_t(i);
      if (points.on_pixel_grid(i)) {  // over its own pixel, as the full render samples it
        for (std::uint32_t s = 0; s < spp; ++s)
          batch.set_ray(std::size_t(n) * spp + s, frustum, pose,
                        pixel_sample_px(screen, int(s), seed, int(view.width_px), settings_.pixel_filter), id);
      } else {
        for (std::uint32_t s = 0; s < spp; ++s) {
          const glm::vec2 offset = precomputed ? sample_offset_px_[i * spp + s]
                                               : unit_disc_sample(seed, id, int(s)) * points.radius_px[i];
          batch.set_ray(std::size_t(n) * spp + s, frustum, pose, screen + offset, id);
        }
      }
      ids[n] = id;
      ++chunk_points;
      if (++n == batch_points) flush();
    }
    if (n > 0) flush();
    traced_points.fetch_add(chunk_points, std::memory_order_relaxed);
  });
  result.trace_ms = ms_since(t_trace);
  result.points = std::uint32_t(traced_points.load());
  result.rays = traced_points.load() * spp;
  result.failed_batches = failed_batches.load();
  result.invalid_colours = invalid_colours.load();
  if (result.failed_batches != 0 || result.invalid_colours != 0) {
    result.failure = result.failed_batches != 0 ? FrameFailure::callback_failed : FrameFailure::invalid_colour;
    result.message = result.failed_batches != 0
                         ? "the ray-trace callback failed " + std::to_string(result.failed_batches) + " batch(es)"
                         : "the ray-trace callback returned " + std::to_string(result.invalid_colours) +
                               " NaN/Inf/negative colour components";
    taa_.reset();
    ray_cache_.clear();
    last_view_.reset();
    return result;
  }
  colors_.invalid = points.size() - result.points;
  // TAA: a new pose, frustum or size either restarts the history (TaaHistory::restart_on_view_change)
  // or has it reprojected; a gaze jump, a saccade or a blink restarts it inside the accumulator.
  const bool moved = !last_view_ || !same_view(*last_view_, view);
  const bool restart = request.saccade || request.blink;
  if (settings_.taa && moved && settings_.taa_history == TaaHistory::restart_on_view_change) taa_.reset();
  // TaaHistory::ray_cache: the frame is the cache's, every ray kept filtered
  // into the pixels around it; the image TAA does not run, only its restart
  // rule (a saccade's or a blink's onset, a gaze jump), which the cache
  // follows unless kept through. A failed frame or the first one restarts it
  // too (the image TAA's history is then empty).
  const bool ray_cache = settings_.taa && settings_.taa_history == TaaHistory::ray_cache;
  const auto t_cache = Clock::now();
  if (ray_cache) {
    const bool history_empty = !last_view_;  // the first frame, or the one after a failed frame
    result.taa_reset = taa_.begin_frame(mapping.screen_width_px, mapping.screen_height_px, mapping.gaze_px, restart);
    result.ray_cache_restart = history_empty || (result.taa_reset && !settings_.ray_cache_keeps_through_saccades);
  }
  if (!settings_.reconstruct_on_cpu) {  // the caller reconstructs: only the TAA rule runs here
    if (ray_cache) {
      prepare_ray_cache_pixels(mapping, true, executor);  // what the caller's cache takes
      result.taa_ms = ms_since(t_cache);
    } else if (settings_.taa) {
      result.taa_reset = taa_.begin_frame(mapping.screen_width_px, mapping.screen_height_px, mapping.gaze_px, restart);
      if (!result.taa_reset && moved) result.history_view = last_view_;  // the caller reprojects from there
    }
    if (settings_.taa) last_view_ = view;
    return result;
  }
  if (ray_cache) {
    filter_through_ray_cache(view, mapping, result.ray_cache_restart, executor);
    result.taa_ms = ms_since(t_cache);
  }

  // Thesis 4.3: every pixel a k-tap gather over the precomputed canvas weights.
  const auto t_gather = Clock::now();
  GatherOptions gather_options;
  gather_options.rbf_clamp = settings_.rbf_clamp;
  result.gather = gather(tables_->neighbors, tables_->interpolation, colors_, mapping, gathered_, executor,
                         gather_options);
  result.reconstruct_ms = ms_since(t_gather);

  const auto t_taa = Clock::now();
  taa_output_ = nullptr;
  if (ray_cache) {
    // Every pixel a ray of the cache reaches shows the cache; any other the gather.
    const int w = int(view.width_px), h = int(view.height_px);
    executor.parallel_for(std::size_t(h), [&](std::size_t y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t p = y * std::size_t(w) + std::size_t(x);
        if (ray_cache_weight_[p] > 0.0f) continue;
        const float* from = gathered_.at(x, int(y));
        float* to = ray_cache_image_.at(x, int(y));
        for (int c = 0; c < 3; ++c) to[c] = from[c];
      }
    });
    taa_output_ = &ray_cache_image_;
    last_view_ = view;
    result.taa_ms += ms_since(t_taa);
    return result;
  }
  if (settings_.taa && settings_.taa_history == TaaHistory::restart_on_view_change) {
    taa_output_ = &taa_.accumulate(gathered_, mapping.gaze_px, executor, restart);
  } else if (settings_.taa) {
    // The history follows the head: reprojected into this view, by depth where the engine gave one.
    if (any_depth.load()) {
      pixel_depths(mapping, executor);
    } else {
      depth_px_m_.clear();
    }
    if (last_view_ && moved && taa_.history().width_px > 0) {
      const ReprojectionStats r = reproject_history(taa_.history(), history_depth_px_m_, *last_view_, view,
                                                    depth_px_m_, warped_, warped_valid_, executor,
                                                    settings_.taa_options.history_sampling);
      result.history_off_screen = r.off_screen;
      result.history_disoccluded = r.disoccluded;
      result.history_with_depth = r.with_depth;
      taa_output_ = &taa_.accumulate_reprojected(gathered_, warped_, warped_valid_, mapping.gaze_px, executor, restart);
    } else {
      taa_output_ = &taa_.accumulate(gathered_, mapping.gaze_px, executor, restart);
    }
    std::swap(history_depth_px_m_, depth_px_m_);
  }
  if (settings_.taa) {
    result.taa_reset = taa_.last_was_reset();
    last_view_ = view;
  }
  result.taa_ms = ms_since(t_taa);
  return result;
}

void FoveatedView::filter_through_ray_cache(const FoveartEyeView& view, const GazeMapping& mapping, bool restart,
                                            Executor& executor) {
  if (restart) ray_cache_.clear();
  ray_cache_.begin_frame(view, executor);
  std::vector<std::size_t>& first = chunk_first_ray_;  // a chunk's rays, in chunk order
  first.assign(chunk_rays_.size() + 1, 0);
  for (std::size_t c = 0; c < chunk_rays_.size(); ++c) first[c + 1] = first[c] + chunk_rays_[c].size();
  const std::size_t base = ray_cache_.add_rays(first.back());
  executor.parallel_for(chunk_rays_.size(), [&](std::size_t c) {
    for (std::size_t i = 0; i < chunk_rays_[c].size(); ++i) {
      const TracedRay& r = chunk_rays_[c][i];
      ray_cache_.set_ray(base + first[c] + i, r.sample_px, r.rgb, r.depth_m, r.pixel);
    }
  });
  prepare_ray_cache_pixels(mapping, false, executor);

  // The periphery's depth test, where this frame has no ray per pixel (the
  // pixel grid's runs inside the cache).
  const int w = int(view.width_px), h = int(view.height_px);
  executor.parallel_chunks(ray_cache_.kept(), 4096, [&](std::size_t first_ray, std::size_t last_ray, unsigned) {
    for (std::size_t i = first_ray; i < last_ray; ++i) {
      const glm::vec2 q = ray_cache_.kept_sample_px(i);
      if (!ray_cache_.kept_on_screen(i) || !(q.x >= 0.0f && q.y >= 0.0f && q.x < float(w) && q.y < float(h))) continue;
      const std::size_t p = std::size_t(q.y) * std::size_t(w) + std::size_t(q.x);
      if (grid_pixel_[p] != 0) continue;
      const float farthest_new_m = ray_cache_pixel_[p].y;
      if (farthest_new_m >= 0.0f && std::isfinite(farthest_new_m) &&
          kept_ray_covered(ray_cache_.distance_m(i), farthest_new_m))
        ray_cache_.forget(i);
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
      const float footprint_px = ray_cache_pixel_[p].x;
      if (footprint_px <= 1.0f) continue;  // the pixel filter itself (resolve)
      periphery_pixels_.push_back(std::uint32_t(p));
      periphery_centre_px_.emplace_back(float(x) + 0.5f, float(y) + 0.5f);
      periphery_footprint_px_.push_back(footprint_px);
    }
  ray_cache_.filter_at(periphery_centre_px_, periphery_footprint_px_, executor, &periphery_rgb_, &periphery_weight_);

  // Every pixel with the pixel filter itself, then the wider filters' pixels over them.
  ray_cache_.resolve(executor, &ray_cache_image_, &ray_cache_weight_);
  executor.parallel_chunks(periphery_pixels_.size(), 4096, [&](std::size_t first_pixel, std::size_t last_pixel,
                                                                 unsigned) {
    for (std::size_t j = first_pixel; j < last_pixel; ++j) {
      const std::size_t p = periphery_pixels_[j];
      ray_cache_weight_[p] = periphery_weight_[j];
      if (periphery_weight_[j] <= 0.0f) continue;
      float* to = ray_cache_image_.rgb.data() + 3 * p;
      for (int c = 0; c < 3; ++c) to[c] = periphery_rgb_[j][c];
    }
  });
}

void FoveatedView::prepare_ray_cache_pixels(const GazeMapping& mapping, bool grid_depth_test, Executor& executor) {
  const PointSet& points = tables_->points;
  const NeighborTable& nt = tables_->neighbors;
  const int w = mapping.screen_width_px, h = mapping.screen_height_px;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  grid_pixel_.assign(pixels, 0);
  if (grid_depth_test) drawn_farthest_m_.assign(pixels, -1.0f);
  executor.parallel_for(chunk_rays_.size(), [&](std::size_t c) {  // a pixel-grid point is in one chunk only
    for (const TracedRay& r : chunk_rays_[c]) {
      if (r.pixel.x < 0 || r.pixel.y < 0 || r.pixel.x >= w || r.pixel.y >= h) continue;
      const std::size_t p = std::size_t(r.pixel.y) * std::size_t(w) + std::size_t(r.pixel.x);
      grid_pixel_[p] = 1;
      if (grid_depth_test) drawn_farthest_m_[p] = std::max(drawn_farthest_m_[p], traced_distance_m(r.depth_m));
    }
  });
  if (grid_depth_test) farthest_around_3x3(drawn_farthest_m_, w, h, executor, &around_farthest_m_);

  // A pixel-grid pixel: the pixel filter, and the 3x3 test. Beyond the grid:
  // the nearest point's disc footprint, and the farthest new ray of the
  // traced points among the k nearest (the 3x3 test's counterpart where this
  // frame has no ray per pixel; a missed or depthless one among them, or
  // none traced, cannot tell).
  ray_cache_pixel_.resize(pixels);
  executor.parallel_for(std::size_t(h), [&](std::size_t y) {
    for (std::size_t x = 0; x < std::size_t(w); ++x) {
      const std::size_t p = y * std::size_t(w) + x;
      if (grid_pixel_[p] != 0) {
        ray_cache_pixel_[p] = glm::vec2(1.0f, grid_depth_test ? around_farthest_m_[p] : NAN);
        continue;
      }
      const std::size_t canvas = mapping.canvas_index(x, y, std::size_t(nt.width_px()));
      const float footprint_px = disc_footprint_px(settings_.pixel_filter, points.radius_px[nt.neighbor(canvas, 0)]);
      float farthest_new_m = -1.0f;
      for (int j = 0; j < nt.k(); ++j) {
        const std::uint32_t n = nt.neighbor(canvas, j);
        if (colors_.rgba[n].a == 0.0f) continue;
        const float d = point_farthest_m_[n];
        farthest_new_m = std::isnan(d) ? INFINITY : std::max(farthest_new_m, d);
      }
      ray_cache_pixel_[p] = glm::vec2(std::max(footprint_px, 1.0f), farthest_new_m);
    }
  });
}

void FoveatedView::pixel_depths(const GazeMapping& mapping, Executor& executor) {
  // A pixel's depth is its nearest traced point's (neighbour order); NaN when none is in reach.
  const NeighborTable& nt = tables_->neighbors;
  const int w = mapping.screen_width_px, h = mapping.screen_height_px;
  depth_px_m_.resize(std::size_t(w) * std::size_t(h));
  executor.parallel_chunks(std::size_t(h), 16, [&](std::size_t y0, std::size_t y1, unsigned) {
    for (std::size_t y = y0; y < y1; ++y) {
      const std::size_t row = mapping.canvas_index(0, y, std::size_t(nt.width_px()));
      for (std::size_t x = 0; x < std::size_t(w); ++x) {
        float depth = NAN;
        for (int j = 0; j < nt.k(); ++j) {
          const std::uint32_t p = nt.neighbor(row + x, j);
          if (colors_.rgba[p].a != 0.0f) {
            depth = point_depth_m_[p];
            break;
          }
        }
        depth_px_m_[y * std::size_t(w) + x] = depth;
      }
    }
  });
}

std::vector<std::uint32_t> points_per_tile(const PointSet& points, const GazeMapping& mapping, std::uint32_t tile_w_px,
                                           std::uint32_t tile_h_px, std::uint32_t tiles_x, std::uint32_t tiles_y) {
  if (tile_w_px == 0 || tile_h_px == 0 || tiles_x == 0 || tiles_y == 0) return {};
  const VisibleRegion visible(mapping, points.visible_margin_px);  // the frame's own test
  const float w = float(mapping.screen_width_px), h = float(mapping.screen_height_px);
  std::vector<std::uint32_t> count(std::size_t(tiles_x) * tiles_y, 0);
  for (const glm::vec2& p : points.position_px) {
    const glm::vec2 screen = visible.to_screen(p);
    if (!visible.contains(screen)) continue;
    const std::uint32_t tx = std::min(tiles_x - 1, std::uint32_t(std::clamp(screen.x, 0.0f, w - 1.0f)) / tile_w_px);
    const std::uint32_t ty = std::min(tiles_y - 1, std::uint32_t(std::clamp(screen.y, 0.0f, h - 1.0f)) / tile_h_px);
    ++count[std::size_t(ty) * tiles_x + tx];
  }
  return count;
}

}  // namespace foveart::foveation
