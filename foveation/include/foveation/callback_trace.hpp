// Stages 1-3 of the frame on the CPU, through the engine's ray-trace callback
// (ray_trace.h; thesis 4.2): in one pass over runs of the point set, each task
// keeps the visible points (stage 1), casts their rays (stage 2), hands them to
// the engine in batches (stage 3), writes each point's mean colour into its
// slot and forgets the points it traced last frame and not this one.
//
// Errors: a failed batch or a bad colour is counted in TraceStats, never thrown.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/content_density.hpp"
#include "foveation/frame_stages.hpp"
#include "foveation/point_rays.hpp"
#include "foveation/point_set.hpp"
#include "foveation/ray_batch.hpp"

namespace foveart::foveation {

class CallbackTrace final : public TraceStage {
 public:
  // `points` must outlive this. keep_rays: also hand on every ray (a history
  // that keeps rays, TemporalHistory::keeps_rays).
  CallbackTrace(const PointSet& points, int rays_per_point, PixelFilter pixel_filter, bool jitter_each_frame,
                bool keep_rays);

  // Thins the points of flat tiles (content_density.hpp); `levels` gives the set's levels
  // at the first frame. With keep_rays a thinned point hands on no ray: its farthest_m is -inf.
  void set_content_density(std::function<const PointLevels&(Executor&)> levels, const ContentDensityOptions& options);

  TraceStats trace(const FrameContext& frame, FrameResources& resources, Executor& executor) override;
  const TracedPoints& traced() const override { return traced_; }

 private:
  struct FramePass;  // one frame's shared state and counts (callback_trace.cpp)
  // The steps of trace: a run of the point set, a batch of its points, their colours kept.
  void trace_run(FramePass& pass, std::size_t run, unsigned worker);
  void forget_untraced(const std::vector<std::uint32_t>& before, std::size_t filled_before,
                       const std::vector<std::uint32_t>& traced, std::size_t run_size);
  void select_run(FramePass& pass, std::size_t run, bool run_visible, std::vector<std::uint32_t>& ids);
  bool trace_batch(FramePass& pass, std::size_t run, unsigned worker, std::span<const std::uint32_t> ids);
  bool keep_ray_colors(const RayBatch& batch, std::span<const std::uint32_t> ids, std::vector<std::uint32_t>& traced);
  bool keep_mean_colors(const FramePass& pass, const RayBatch& batch, std::span<const std::uint32_t> ids,
                        std::span<const std::uint32_t> counts, std::size_t run);
  // Content-aware density: the per-point test, this run's traced colours for the next
  // frame's contrast, and the thinned points' colours from their parents (after every run).
  void thin_run(FramePass& pass, std::size_t run, std::vector<std::uint32_t>& ids);
  void count_rays(FramePass& pass, std::span<const std::uint32_t> ids, std::vector<std::uint32_t>& counts) const;
  void observe_run(FramePass& pass, std::size_t run, unsigned worker);
  std::uint64_t fill_thinned(Executor& executor);
  bool fill_point(std::uint32_t id);

  const PointSet& points_;
  PointRays rays_;
  bool keep_rays_;
  TracedPoints traced_;
  std::vector<RayBatch> batches_;                         // per worker slot
  std::vector<std::vector<std::uint32_t>> batch_points_;  // per worker slot: its run's points to trace
  std::vector<std::vector<std::uint32_t>> previous_;      // per worker slot: its run's points of last frame
  std::vector<std::vector<std::uint32_t>> batch_counts_;  // per worker slot: its batch's rays per point (empty: all)
  // Per run of the point set, the canvas box its points lie in: a run wholly
  // off the screen is skipped without testing its points one by one.
  struct RunBox {
    glm::vec2 min_px, max_px;
  };
  std::vector<RunBox> run_boxes_;
  std::function<const PointLevels&(Executor&)> levels_of_set_;
  ContentDensityOptions density_options_;
  std::optional<ContentDensity> density_;
  std::vector<std::vector<std::uint32_t>> thinned_;  // per run: visible points this frame does not trace
  // Per run: where the filled points begin in traced_.runs (the traced ones come first).
  std::vector<std::uint32_t> filled_begin_;
};

}  // namespace foveart::foveation
