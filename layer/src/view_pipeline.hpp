// The CPU frame path of one eye (ARCHITECTURE.md, "One frame, end to end"):
// gaze -> visible points -> jittered ray samples -> engine callback in batches
// on the worker pool -> one colour per point -> k-tap gather over the canvas
// neighbour table -> temporal accumulation (TAA) -> RGBA8 for upload.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "foveation/gather.hpp"
#include "foveation/interpolation_cache.hpp"
#include "foveation/interpolation_table.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/srgb.hpp"
#include "foveation/taa.hpp"
#include "foveation/visible_points.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "renderer.hpp"
#include "worker_pool.hpp"

namespace foveart::layer {

struct ViewTables {
  foveation::PointSet points;
  foveation::NeighborTable neighbors;
  foveation::InterpolationTable interpolation;  // per-canvas-pixel weights of the method
};

// The interpolation options for a renderer's settings (method, k).
foveation::InterpOptions interp_options(const RendererSettings& settings);
// Neighbours per canvas pixel the tables need: k, and at least 4 for NN so a
// pixel whose nearest point was not traced finds another (as fovea render does).
int neighbor_count(const RendererSettings& settings);
// Builds (or loads from cache_dir) every table for one eye's display.
std::shared_ptr<const ViewTables> load_view_tables(const foveation::PointSetKey& key, const RendererSettings& settings,
                                                   const std::optional<std::filesystem::path>& cache_dir);

struct ViewRequest {
  uint32_t eye_index = 0;
  uint64_t frame_index = 0;
  XrPosef pose{};
  XrFovf fov{};
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  glm::vec2 gaze_px{};  // where the eye looks, in this eye's pixels
};

struct ViewOutcome {
  bool ok = false;
  XrFoveatedFallbackFlagsFOVEART failure = 0;  // why not ok
  std::string message;                         // first failure, for the log
  uint32_t points = 0;
  uint32_t rays = 0;
  float select_ms = 0, trace_ms = 0, interpolate_ms = 0, taa_ms = 0;
  uint64_t callback_failures = 0;  // batches
  uint64_t invalid_colours = 0;    // rays
};

class ViewPipeline {
 public:
  // points_per_chunk: points of the point set per selection task on the pool.
  explicit ViewPipeline(std::shared_ptr<const ViewTables> tables, std::size_t points_per_chunk = 32768);

  // Fills out_rgba (width*height RGBA8, sRGB-encoded when srgb) or returns !ok
  // and leaves out_rgba untouched.
  ViewOutcome render(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool,
                     uint8_t* out_rgba, bool srgb);

 private:
  bool trace(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool, ViewOutcome* outcome);

  std::shared_ptr<const ViewTables> tables_;
  std::size_t points_per_chunk_;
  std::vector<float> origins_, directions_, sample_px_, ray_rgb_;
  std::vector<uint32_t> point_index_;
  std::vector<uint32_t> visible_index_;  // the visible points, in order
  std::vector<foveation::VisiblePoints> chunks_;       // selection per chunk of the point set
  std::vector<std::vector<glm::vec2>> chunk_samples_;  // their ray samples
  std::vector<std::size_t> chunk_offset_;             // first visible point of each chunk
  std::vector<float> point_rgb_;         // 3 floats per visible point
  foveation::GazeMapping mapping_;
  foveation::ImageRgb image_;
  foveation::TemporalAccumulator taa_;
  ViewRequest last_{};
  bool has_last_ = false;
};

// Linear [0,1] -> sRGB 8 bit (IEC 61966-2-1), exactly as `fovea` writes PNGs.
using foveation::encode_srgb8;

}  // namespace foveart::layer
