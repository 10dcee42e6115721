// The one foveated frame (thesis 4.2-4.3; docs/design.md "One frame, end to
// end"), used by the OpenXR layer, `fovea render` and `fovea reconstruct`
// alike: the visible points of the point set at the gaze -> jittered rays in
// each point's disc -> the engine callback, in batches on the executor ->
// one colour per point (colour checks) -> every pixel a k-tap gather over the
// canvas tables (NN, MSM and RBF alike) -> temporal accumulation.
//
// Lifetime and threads: a FoveatedView belongs to one view (one eye of one
// display); render() is called from one thread at a time and spreads its work
// over the executor it is given. The tables are shared and immutable.
// Errors: render() never throws for anything the engine does (a failed batch or
// a NaN colour is reported in FrameResult); it throws std::invalid_argument
// when a request does not fit the tables (a programming error of the caller).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "foveation/executor.hpp"
#include "foveation/foveation_centre.hpp"
#include "foveation/gather.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/interpolation_table.hpp"
#include "foveation/interpolation_weights.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/ray_batch.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/ray_trace.h"
#include "foveation/taa.hpp"

namespace foveart::foveation {

// Everything a view's frames read that depends only on the display: the point
// set, the k nearest points of every canvas pixel and the method's weights.
struct ViewTables {
  PointSetKey key;
  PointSet points;
  NeighborTable neighbors;
  InterpolationTable interpolation;
  bool from_cache = false;  // all three loaded from the cache directory
  double load_ms = 0.0;     // load or build, all three
};

// The display whose tables fit a submitted view: its size and its horizontal
// span (DisplayModel::from_fov), from the view's float angles. The layer and
// `fovea render --fov` both call this, so they build the same point set.
DisplayModel display_of_view(const FoveartEyeView& view);

// Neighbours per canvas pixel the tables keep for a method: k, and at least 4
// for NN, so that a pixel whose nearest point was not traced (beyond the
// visible margin) falls back to the next nearest traced one.
int neighbor_count(const InterpOptions& interpolation);

// Loads the tables of `key.display` from `cache_dir` (nullopt: no cache) or
// builds and stores them. key.k is set from the method. Rejected cache files go
// to `log`; build errors throw.
std::shared_ptr<const ViewTables> load_view_tables(const std::optional<std::filesystem::path>& cache_dir,
                                                   PointSetKey key, const InterpOptions& interpolation,
                                                   Executor& executor,
                                                   std::optional<WeightPrecision> precision = std::nullopt,
                                                   const ProgressFn& progress = {}, const LogFn& log = {});

// What the TAA history does when the view moves (thesis 6.1 had a static view).
enum class TaaHistory : std::uint8_t {
  restart_on_view_change,  // any new pose or frustum restarts the history (FoveaRT before reprojection)
  reproject,               // the history follows the head: rotation, and parallax from the engine's depth
  // every traced ray kept in a render cache (ray_cache.hpp) instead of an
  // image: each is anchored where it hit and filtered, with this frame's,
  // into the pixels around where it now lies: with the pixel filter over
  // this frame's pixel grid, widened to the nearest point's disc beyond it
  // (the Poisson periphery). On the CPU, or with reconstruct_on_cpu = false
  // in a cache elsewhere (the layer's GPU path, shaders/cache_*.comp).
  ray_cache,
};

struct ViewSettings {
  int rays_per_point = 1;            // jittered rays in each point's disc, averaged (thesis 4.2)
  std::uint64_t sample_seed = 1;     // where in its disc each ray goes
  PixelFilter pixel_filter = PixelFilter::box;  // how a pixel-grid point's rays spread (ray_samples.hpp)
  bool new_jitter_each_frame = false;  // sample_seed + frame_index: TAA then converges over frames
  bool taa = false;                  // temporal accumulation (thesis 2.5, 6.1)
  TaaOptions taa_options;            // for 1 ray per point; more rays blend with taa_options_for_rays
  TaaHistory taa_history = TaaHistory::reproject;
  // TaaHistory::ray_cache: a kept ray is forgotten this many frames after it
  // was traced (bounds the rays kept on a still view; 0: never) ...
  std::uint32_t ray_cache_max_age_frames = 32;
  // ... and all of them at the image TAA's restarts (the onset of a saccade
  // or a blink, a gaze jump) unless this is set: its rays are
  // anchored in the world, so a gaze jump leaves no ghost to clear.
  bool ray_cache_keeps_through_saccades = false;
  RbfClamp rbf_clamp = RbfClamp::block;
  // The foveation centre stays put while the gaze stays within this many
  // degrees of it (fixation: microsaccades, drift, tracker noise), and jumps
  // to the gaze at once beyond it or on a saccade or blink: a steady fixation
  // keeps a steady point pattern, a real gaze shift adds no latency (docs/foveation.md).
  // 0: the centre follows every whole-pixel gaze change.
  double centre_deadband_deg = 1.0;
  // false: render() stops after the colours and the TAA reset decision; the
  // caller reconstructs from colors() and traced() (the layer's GPU path).
  bool reconstruct_on_cpu = true;
};

struct FrameRequest {
  FoveartEyeView view{};       // pose, frustum and size; the size must be the tables' display
  glm::vec2 gaze_px{};         // the gaze in this view's pixels (rounded to whole pixels); the centre follows it
  std::uint64_t frame_index = 0;
  bool saccade = false;        // the gaze provider saw a saccade: the TAA history restarts
  bool blink = false;          // the eye is closed (the provider holds its last gaze): the history restarts
};

enum class FrameFailure : std::uint8_t {
  none = 0,
  callback_failed,  // the engine returned an error for a batch (or threw)
  invalid_colour,   // a colour component was NaN, infinite or negative
};

struct FrameResult {
  FrameFailure failure = FrameFailure::none;
  std::string message;              // the failure, for a log line
  std::uint32_t points = 0;         // visible points traced
  std::uint64_t rays = 0;           // primary rays handed to the engine
  std::uint64_t failed_batches = 0;
  std::uint64_t invalid_colours = 0;  // colour components
  double select_ms = 0.0;           // forget last frame's points (selection itself runs inside the trace pass)
  double trace_ms = 0.0;            // visible-point test, rays, engine callback, colour per point
  double reconstruct_ms = 0.0;      // gather
  double taa_ms = 0.0;
  glm::vec2 centre_px{};            // the foveation centre this frame used (ViewSettings::centre_deadband_deg)
  bool taa_reset = false;           // the history restarted this frame
  std::uint64_t history_off_screen = 0;   // TaaHistory::reproject: pixels whose surface was off the last view
  std::uint64_t history_disoccluded = 0;  // ... whose last depth disagreed (a surface uncovered)
  std::uint64_t history_with_depth = 0;   // ... reprojected through the engine's depth (the rest: rotation only)
  // reconstruct_on_cpu = false: the view the history was rendered from when
  // this frame must reproject it (TaaHistory::reproject, the view moved, no reset).
  std::optional<FoveartEyeView> history_view;
  // TaaHistory::ray_cache: the cache restarts this frame (a restart the cache
  // is not kept through, a failed frame before it, or the first frame).
  bool ray_cache_restart = false;
  GatherStats gather;

  bool ok() const { return failure == FrameFailure::none; }
};

class FoveatedView {
 public:
  FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings);

  // One frame. On success image() holds it; on failure image() keeps the last
  // good frame and the TAA history restarts.
  FrameResult render(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                     Executor& executor);

  // The last successful frame (after TAA when it is on), in the callback's
  // colour space (linear RGB from an engine).
  const ImageRgb& image() const { return taa_output_ != nullptr ? *taa_output_ : gathered_; }
  // TaaHistory::ray_cache: the rays its render cache keeps after the last frame.
  std::size_t cached_rays() const { return ray_cache_.size(); }
  // TaaHistory::ray_cache with reconstruct_on_cpu = false, what a render
  // cache elsewhere (the layer's GPU path) takes from the last frame: its
  // traced rays in runs, and per screen pixel (row-major) x, the footprint at
  // which the cache filters there (1: the pixel filter itself; wider beyond
  // the pixel grid, disc_footprint_px), and y, the distance beyond which a
  // kept ray landing in the pixel is covered (kept_ray_covered; not finite
  // or negative: this frame cannot tell).
  const std::vector<std::vector<TracedRay>>& traced_rays() const { return chunk_rays_; }
  const std::vector<glm::vec2>& ray_cache_pixels() const { return ray_cache_pixel_; }
  // The same frame before TAA: the reconstruction alone.
  const ImageRgb& reconstructed() const { return gathered_; }
  // The last frame's colour per point of the set (a = 1: traced) and the
  // points it traced, in runs: what a reconstruction elsewhere needs.
  const PointColors& colors() const { return colors_; }
  const std::vector<std::vector<std::uint32_t>>& traced() const { return traced_; }
  // The last frame's depth per point (nearest hit of its rays; NaN: none returned).
  const std::vector<float>& point_depths() const { return point_depth_m_; }
  const ViewTables& tables() const { return *tables_; }
  const ViewSettings& settings() const { return settings_; }
  // What the TAA blends with: settings().taa_options for its rays per point
  // (taa_options_for_rays).
  const TaaOptions& taa_options() const { return taa_.options(); }
  // The last frame's TAA blend weight (1 on a reset; the mean's 1 / k while
  // the history is young): TemporalAccumulator::frame_weight().
  float taa_frame_weight() const { return taa_.frame_weight(); }

 private:
  void pixel_depths(const GazeMapping& mapping, Executor& executor);  // depth_px_m_ from point_depth_m_
  // TaaHistory::ray_cache: this frame's rays into the cache, and the cache's
  // pixels into ray_cache_image_ (ray_cache_weight_ 0 where no ray reaches).
  void filter_through_ray_cache(const FoveartEyeView& view, const GazeMapping& mapping, bool restart,
                                Executor& executor);
  // TaaHistory::ray_cache: grid_pixel_ and ray_cache_pixel_ of this frame
  // (with the pixel grid's depth test too when `grid_depth_test`: a cache elsewhere).
  void prepare_ray_cache_pixels(const GazeMapping& mapping, bool grid_depth_test, Executor& executor);

  std::shared_ptr<const ViewTables> tables_;
  ViewSettings settings_;
  PointColors colors_;                    // one slot per point of the set; a = 1 traced this frame
  std::vector<float> point_depth_m_;      // per point: nearest hit of its rays (NaN: none returned)
  std::vector<float> depth_px_m_, history_depth_px_m_;  // per screen pixel, this and the last frame (empty: none)
  ImageRgb warped_;                       // the history reprojected into this frame's view
  std::vector<std::uint8_t> warped_valid_;
  std::vector<std::vector<std::uint32_t>> traced_;  // per chunk of the point set: its points traced last frame
  std::vector<RayBatch> batches_;         // per worker slot
  std::vector<std::vector<std::uint32_t>> batch_points_;  // per worker slot: the points of its batch
  std::vector<glm::vec2> sample_offset_px_;  // precomputed disc offsets for a fixed seed (empty: made per frame)
  std::uint64_t sample_offset_seed_ = 0;
  ImageRgb gathered_;
  TemporalAccumulator taa_;
  RayCache ray_cache_;                     // TaaHistory::ray_cache
  std::vector<float> point_farthest_m_;  // per point: farthest hit of its rays (NaN: one gave none)
  // This frame's pixels beyond its pixel grid, their filters' scale, and the cache's filter there.
  std::vector<std::uint32_t> periphery_pixels_;
  std::vector<glm::vec2> periphery_centre_px_;
  std::vector<float> periphery_footprint_px_, periphery_weight_;
  std::vector<glm::vec3> periphery_rgb_;
  std::vector<std::vector<TracedRay>> chunk_rays_;  // per chunk of the point set: its rays traced this frame
  std::vector<std::size_t> chunk_first_ray_;   // chunk c's rays start at chunk_first_ray_[c] among the frame's
  std::vector<std::uint8_t> grid_pixel_;       // per screen pixel: a pixel-grid point's this frame (the cache's)
  std::vector<glm::vec2> ray_cache_pixel_;     // per screen pixel: ray_cache_pixels()
  std::vector<float> drawn_farthest_m_, around_farthest_m_;  // the pixel grid's depth test, for a cache elsewhere
  ImageRgb ray_cache_image_;
  std::vector<float> ray_cache_weight_;
  const ImageRgb* taa_output_ = nullptr;
  std::optional<FoveartEyeView> last_view_;  // the TAA history's view
  FoveationCentre centre_;                   // held through fixations (ViewSettings::centre_deadband_deg)
};

// Points a frame at `mapping` traces per tile of a tiles_x x tiles_y grid of
// tile_w x tile_h screen tiles (row-major; points in the margin beyond the
// screen count in the nearest tile). Empty for an empty grid.
std::vector<std::uint32_t> points_per_tile(const PointSet& points, const GazeMapping& mapping, std::uint32_t tile_w_px,
                                           std::uint32_t tile_h_px, std::uint32_t tiles_x, std::uint32_t tiles_y);

}  // namespace foveart::foveation
