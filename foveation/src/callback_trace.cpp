#include "foveation/callback_trace.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>

#include "foveation/visible_points.hpp"
#include "foveation/elapsed.hpp"

namespace foveart::foveation {
namespace {

// Rays per engine callback call, and points of the set per parallel task: a
// task is a contiguous run of the Hilbert order (the rays of a packet are
// neighbours on the screen), small enough that the last task of a frame keeps
// the other threads idle only briefly.
constexpr std::uint32_t kBatchRays = 4096;
constexpr std::size_t kRunPoints = 2048;

using Clock = std::chrono::steady_clock;

}  // namespace

CallbackTrace::CallbackTrace(const PointSet& points, int rays_per_point, PixelFilter pixel_filter,
                             bool jitter_each_frame, bool keep_rays)
    : points_(points), rays_(points, rays_per_point, pixel_filter, jitter_each_frame), keep_rays_(keep_rays) {
  traced_.colors.rgba.assign(points.size(), Rgba{});
  traced_.colors.invalid = points.size();
  traced_.depth_m.assign(points.size(), NAN);
  traced_.rays_cast.assign(points.size(), 0);
  traced_.runs.resize((points.size() + kRunPoints - 1) / kRunPoints);
  filled_begin_.assign(traced_.runs.size(), 0);
  run_boxes_.resize(traced_.runs.size(), RunBox{glm::vec2(INFINITY), glm::vec2(-INFINITY)});
  for (std::size_t i = 0; i < points.size(); ++i) {
    RunBox& box = run_boxes_[i / kRunPoints];
    box.min_px = glm::min(box.min_px, points.position_px[i]);
    box.max_px = glm::max(box.max_px, points.position_px[i]);
  }
  if (keep_rays_) {
    traced_.rays.resize(traced_.runs.size());
    traced_.farthest_m.assign(points.size(), NAN);
  }
}

void CallbackTrace::set_content_density(std::function<const PointLevels&(Executor&)> levels,
                                        const ContentDensityOptions& options) {
  levels_of_set_ = std::move(levels);
  density_options_ = options;
  density_.reset();
  thinned_.assign(traced_.runs.size(), {});
}

// One frame's pass over the runs: what every run reads, and the counts they add to.
struct CallbackTrace::FramePass {
  const FrameContext& frame;
  const VisibleRegion visible;
  const std::uint32_t spp;           // rays per point
  const std::uint32_t batch_points;  // points per engine call
  const float inv_spp;
  ContentDensity* density;            // null: every visible point is traced
  const bool varies_rays;             // rays per point by the content (point_rays.hpp)
  const RaysContrastSteps rays_contrast;  // when they vary: the contrast from which a point casts all
  std::atomic<std::uint64_t> traced_points{0}, traced_rays{0}, failed_batches{0}, invalid_colours{0};
  std::atomic<bool> any_depth{false};
  // Content density's per-point test and observations, CPU time summed over the workers.
  std::atomic<double> test_ms{0.0}, observe_ms{0.0};
};

TraceStats CallbackTrace::trace(const FrameContext& frame, FrameResources&, Executor& executor) {
  if (frame.trace_rays == nullptr) throw std::invalid_argument("foveated view: no ray-trace callback");
  TraceStats stats;
  const auto t_setup = Clock::now();
  const std::uint32_t spp = rays_.rays_per_point();
  rays_.prepare(frame.sample_seed, executor);
  const unsigned workers = executor.thread_count();
  const std::uint32_t batch_points = std::max<std::uint32_t>(1, kBatchRays / spp);
  if (batches_.size() < workers) {
    batches_.resize(workers);
    batch_points_.resize(workers);
    previous_.resize(workers);
    batch_counts_.resize(workers);
  }
  const auto t_density = Clock::now();
  if (levels_of_set_ && density_options_.enabled() && !density_)
    density_.emplace(levels_of_set_(executor), density_options_);  // the levels: once per table set
  if (density_) density_->begin_frame(frame.mapping, workers);
  const double levels_ms = ms_since(t_density);
  stats.select_ms = ms_since(t_setup);

  const auto t_trace = Clock::now();
  const RaysContrastSteps rays_contrast =
      density_ ? rays_contrast_steps(density_->options().rays_contrast, density_->options().rays_doubling_ecc_deg,
                                     points_.view_distance_px)
               : RaysContrastSteps{};
  FramePass pass{frame, VisibleRegion(frame.mapping, points_.visible_margin_px), spp, batch_points, 1.0f / float(spp),
                 density_ ? &*density_ : nullptr, density_ && density_->options().varies_rays(), rays_contrast};
  executor.parallel_for(traced_.runs.size(), [&](std::size_t run, unsigned worker) { trace_run(pass, run, worker); });
  const auto t_fill = Clock::now();
  const std::uint64_t filled = density_ ? fill_thinned(executor) : 0;
  if (density_) {
    stats.density = DensityCost{levels_ms, pass.test_ms.load() / double(workers),
                                pass.observe_ms.load() / double(workers), ms_since(t_fill)};
    stats.density_ms = stats.density.total_ms();
  }
  stats.trace_ms = ms_since(t_trace);
  stats.points = std::uint32_t(pass.traced_points.load());
  stats.points_thinned = std::uint32_t(filled);
  stats.rays = pass.traced_rays.load();
  stats.failed_batches = pass.failed_batches.load();
  stats.invalid_colours = pass.invalid_colours.load();
  traced_.any_depth = pass.any_depth.load();
  if (stats.ok()) traced_.colors.invalid = points_.size() - stats.points - filled;
  if (density_) density_->end_frame(stats.ok());
  return stats;
}

// Only the points traced hold a colour. Last frame's points of this run that
// this frame does not trace are cleared after it (forget_untraced), rather than
// all of them before: most are traced again and overwritten.
void CallbackTrace::trace_run(FramePass& pass, std::size_t run, unsigned worker) {
  std::vector<std::uint32_t>& traced = traced_.runs[run];
  std::vector<std::uint32_t>& before = previous_[worker];
  before.swap(traced);
  traced.clear();
  const std::size_t filled_before = std::min<std::size_t>(filled_begin_[run], before.size());
  if (pass.density != nullptr) thinned_[run].clear();
  const std::size_t first = run * kRunPoints, last = std::min(points_.size(), first + kRunPoints);
  if (keep_rays_) traced_.rays[run].clear();
  const VisibleRegion& visible = pass.visible;
  const RunBox& box = run_boxes_[run];
  const glm::vec2 box_min = visible.to_screen(box.min_px), box_max = visible.to_screen(box.max_px);
  if (box_max.x < visible.x0 || box_min.x >= visible.x1 || box_max.y < visible.y0 || box_min.y >= visible.y1) {
    forget_untraced(before, filled_before, traced, last - first);
    filled_begin_[run] = 0;
    return;  // no point of this run is on the screen
  }
  // Most runs lie wholly on the screen: their points need no test of their own.
  const bool run_visible = visible.contains(box_min) && visible.contains(box_max);
  std::vector<std::uint32_t>& ids = batch_points_[worker];
  select_run(pass, run, run_visible, ids);
  batches_[worker].resize(std::size_t(pass.batch_points) * pass.spp);
  bool run_has_depth = false;  // written once per run: a shared flag stored per point bounces between cores
  for (std::size_t b = 0; b < ids.size(); b += pass.batch_points) {  // stages 2 and 3
    const std::span<const std::uint32_t> batch(ids.data() + b, std::min<std::size_t>(pass.batch_points, ids.size() - b));
    if (trace_batch(pass, run, worker, batch)) run_has_depth = true;
  }
  if (pass.density != nullptr) observe_run(pass, run, worker);
  forget_untraced(before, filled_before, traced, last - first);
  filled_begin_[run] = std::uint32_t(traced.size());  // fill_thinned appends after them
  pass.traced_points.fetch_add(ids.size(), std::memory_order_relaxed);
  if (run_has_depth) pass.any_depth.store(true, std::memory_order_relaxed);
}

// Stage 1 over a run: its visible points into `ids` (ascending); then content density's
// per-point test.
void CallbackTrace::select_run(FramePass& pass, std::size_t run, bool run_visible, std::vector<std::uint32_t>& ids) {
  const std::size_t first = run * kRunPoints, last = std::min(points_.size(), first + kRunPoints);
  const VisibleRegion& visible = pass.visible;
  ids.clear();
  for (std::size_t i = first; i < last; ++i)
    if (run_visible || visible.contains(visible.to_screen(points_.position_px[i]))) ids.push_back(std::uint32_t(i));
  if (pass.density != nullptr) thin_run(pass, run, ids);
}

// Content density's per-point test over a run's visible points: a flat tile's finer points
// move from `ids` to thinned_[run] (filled after the pass). The levels of the tiles under
// the run's box settle most points by their level alone; only a point of a level between
// them looks up its tile. A point whose nearest parent lies beyond the margin is traced.
void CallbackTrace::thin_run(FramePass& pass, std::size_t run, std::vector<std::uint32_t>& ids) {
  const auto t0 = Clock::now();
  const VisibleRegion& visible = pass.visible;
  const ContentDensity& density = *pass.density;
  const RunBox& box = run_boxes_[run];
  const auto [lowest, highest] = density.levels_under(visible.to_screen(box.min_px), visible.to_screen(box.max_px));
  if (lowest < PointLevels::kFinest) {
    const PointLevels& levels = density.levels();
    const auto parent_visible = [&](std::uint32_t parent) {
      return parent != PointLevels::kNoParent && visible.contains(visible.to_screen(points_.position_px[parent]));
    };
    std::size_t kept = 0;
    for (const std::uint32_t id : ids) {
      const std::uint8_t level = levels.level[id];
      const bool traced =
          level <= lowest || (level <= highest && density.traces(id, visible.to_screen(points_.position_px[id])));
      if (traced || !parent_visible(levels.parent[id][0]))
        ids[kept++] = id;
      else
        thinned_[run].push_back(id);
    }
    ids.resize(kept);
  }
  pass.test_ms.fetch_add(ms_since(t0), std::memory_order_relaxed);
}

// Clears the colour and depth of the points in `before` (last frame's, of a
// run of run_size points) that are not in `traced` (this frame's). `before` is
// two ascending lists: the points traced, then from filled_before those filled.
void CallbackTrace::forget_untraced(const std::vector<std::uint32_t>& before, std::size_t filled_before,
                                    const std::vector<std::uint32_t>& traced, std::size_t run_size) {
  if (traced.size() == run_size) return;  // every point of the run holds this frame's colour
  const auto forget = [&](auto begin, auto end) {
    auto now = traced.begin();  // both ascend (the run's order)
    for (auto it = begin; it != end; ++it) {
      while (now != traced.end() && *now < *it) ++now;
      if (now == traced.end() || *now != *it) {
        traced_.colors.rgba[*it] = Rgba{};
        traced_.depth_m[*it] = NAN;
        traced_.rays_cast[*it] = 0;
      }
    }
  };
  forget(before.begin(), before.begin() + std::ptrdiff_t(filled_before));
  forget(before.begin() + std::ptrdiff_t(filled_before), before.end());
}

// Stages 2 and 3 for a batch of the worker's run: their rays, the engine's colours,
// each point's colour and depth. True if a point got a depth.
bool CallbackTrace::trace_batch(FramePass& pass, std::size_t run, unsigned worker, std::span<const std::uint32_t> ids) {
  RayBatch& batch = batches_[worker];
  std::vector<std::uint32_t>& counts = batch_counts_[worker];
  count_rays(pass, ids, counts);
  const std::uint32_t rays = rays_.set_rays(batch, ids, pass.visible, int(pass.frame.view.width_px), counts);  // stage 2
  pass.traced_rays.fetch_add(rays, std::memory_order_relaxed);
  if (batch.trace(pass.frame.trace_rays, pass.frame.user_data, pass.frame.view, pass.frame.frame_index, rays) !=
      FOVEART_RESULT_SUCCESS) {
    pass.failed_batches.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (const std::uint64_t bad = batch.invalid_components(rays); bad != 0) {
    pass.invalid_colours.fetch_add(bad, std::memory_order_relaxed);
    return false;
  }
  if (pass.spp == 1 && !keep_rays_) return keep_ray_colors(batch, ids, traced_.runs[run]);  // the common frame
  return keep_mean_colors(pass, batch, ids, counts, run);
}

// A ray per point: its colour and its hit distance are the point's.
bool CallbackTrace::keep_ray_colors(const RayBatch& batch, std::span<const std::uint32_t> ids,
                                    std::vector<std::uint32_t>& traced) {
  PointColors& colors = traced_.colors;
  bool any_depth = false;
  for (std::uint32_t j = 0; j < ids.size(); ++j) {
    const glm::vec3 c = batch.rgb(j);
    const float d = batch.depth_m(j);
    const bool has_depth = d >= 0.0f;
    colors.rgba[ids[j]] = Rgba{c.x, c.y, c.z, 1.0f};
    traced_.depth_m[ids[j]] = has_depth ? d : NAN;
    traced_.rays_cast[ids[j]] = 1;
    any_depth = any_depth || has_depth;
  }
  traced.insert(traced.end(), ids.begin(), ids.end());
  return any_depth;
}

// Several rays per point, or the rays kept: each point's mean colour, its
// nearest and farthest hit and, with keep_rays_, every ray of the run.
bool CallbackTrace::keep_mean_colors(const FramePass& pass, const RayBatch& batch, std::span<const std::uint32_t> ids,
                                     std::span<const std::uint32_t> counts, std::size_t run) {
  PointColors& colors = traced_.colors;
  std::vector<std::uint32_t>& traced = traced_.runs[run];
  bool any_depth = false;
  for (std::uint32_t j = 0, r = 0; j < ids.size(); ++j) {
    glm::vec3 sum(0.0f);
    float nearest_m = NAN;    // the point's depth: its nearest hit (NaN: the engine gave none)
    float farthest_m = 0.0f;  // its farthest (NaN: one gave none), for the ray cache's depth test
    // A pixel-grid ray is drawn for its point's pixel; a Poisson point's for none.
    const glm::ivec2 pixel = keep_rays_ && points_.on_pixel_grid(ids[j])
                                 ? glm::ivec2(glm::floor(pass.visible.to_screen(points_.position_px[ids[j]])))
                                 : glm::ivec2(-1);
    const std::uint32_t rays = counts.empty() ? pass.spp : counts[j];
    for (std::uint32_t s = 0; s < rays; ++s, ++r) {
      sum += batch.rgb(r);
      const float d = batch.depth_m(r);
      if (d >= 0.0f && !(d >= nearest_m)) nearest_m = d;  // NaN and negative ignored
      farthest_m = d >= 0.0f ? std::max(farthest_m, d) : NAN;
      if (keep_rays_) traced_.rays[run].push_back(TracedRay{batch.sample_px(r), batch.rgb(r), d, pixel});
    }
    sum *= counts.empty() ? pass.inv_spp : 1.0f / float(rays);
    colors.rgba[ids[j]] = Rgba{sum.x, sum.y, sum.z, 1.0f};
    traced_.depth_m[ids[j]] = nearest_m;
    traced_.rays_cast[ids[j]] = std::uint16_t(rays);
    if (keep_rays_) traced_.farthest_m[ids[j]] = farthest_m;
    any_depth = any_depth || !std::isnan(nearest_m);
    traced.push_back(ids[j]);
  }
  return any_depth;
}

// Rays per point by the tile's contrast (point_rays.hpp) into `counts`; empty: every point casts all.
void CallbackTrace::count_rays(FramePass& pass, std::span<const std::uint32_t> ids,
                               std::vector<std::uint32_t>& counts) const {
  counts.clear();
  if (!pass.varies_rays) return;
  const auto t0 = Clock::now();
  for (const std::uint32_t id : ids)
    counts.push_back(
        rays_.rays_of(id, pass.density->contrast(pass.visible.to_screen(points_.position_px[id])), pass.rays_contrast));
  pass.test_ms.fetch_add(ms_since(t0), std::memory_order_relaxed);
}

void CallbackTrace::observe_run(FramePass& pass, std::size_t run, unsigned worker) {
  const auto t0 = Clock::now();
  for (std::uint32_t id : traced_.runs[run])
    pass.density->observe(worker, pass.visible.to_screen(points_.position_px[id]), traced_.colors.rgba[id]);
  pass.observe_ms.fetch_add(ms_since(t0), std::memory_order_relaxed);
}

// Each thinned point takes the inverse-distance mean of its traced parents
// (point_levels.hpp) and joins its run's list after the traced ones (from
// filled_begin_), both ascending: no merge, which would allocate per run and frame.
std::uint64_t CallbackTrace::fill_thinned(Executor& executor) {
  std::atomic<std::uint64_t> filled{0};
  executor.parallel_for(traced_.runs.size(), [&](std::size_t run) {
    std::vector<std::uint32_t>& thinned = thinned_[run];
    if (thinned.empty()) return;
    thinned.erase(std::remove_if(thinned.begin(), thinned.end(), [&](std::uint32_t id) { return !fill_point(id); }),
                  thinned.end());
    std::vector<std::uint32_t>& list = traced_.runs[run];
    list.insert(list.end(), thinned.begin(), thinned.end());
    filled.fetch_add(thinned.size(), std::memory_order_relaxed);
  });
  return filled.load();
}

// False when no parent was traced this frame (the point then stays without a colour).
bool CallbackTrace::fill_point(std::uint32_t id) {
  const PointLevels& levels = density_->levels();
  std::vector<Rgba>& rgba = traced_.colors.rgba;
  glm::vec3 sum(0.0f);
  float weight = 0.0f, depth_m = NAN;
  for (std::uint32_t j = 0; j < PointLevels::kParents; ++j) {
    const std::uint32_t parent = levels.parent[id][j];
    if (parent == PointLevels::kNoParent || rgba[parent].a != 1.0f) continue;
    const float w = levels.parent_weight[id][j];
    sum += w * glm::vec3(rgba[parent].r, rgba[parent].g, rgba[parent].b);
    if (weight == 0.0f) depth_m = traced_.depth_m[parent];  // the nearest traced parent's
    weight += w;
  }
  if (weight <= 0.0f) return false;
  sum /= weight;
  rgba[id] = Rgba{sum.x, sum.y, sum.z, 1.0f};
  traced_.depth_m[id] = depth_m;
  traced_.rays_cast[id] = 0;                           // its colour is its parents' rays
  if (keep_rays_) traced_.farthest_m[id] = -INFINITY;  // no ray of its own: no farthest hit for the ray history
  return true;
}

}  // namespace foveart::foveation
