// The CPU frame path of one eye (ARCHITECTURE.md, "One frame, end to end"):
// gaze -> visible points -> jittered ray samples -> engine callback in batches
// on the worker pool -> one colour per point -> k-tap gather over the canvas
// neighbour table -> temporal accumulation (TAA) -> RGBA8 for upload.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "renderer.hpp"
#include "worker_pool.hpp"

namespace foveart::layer {

struct ViewTables {
  foveation::PointSet points;
  foveation::NeighborTable neighbors;
};

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
  explicit ViewPipeline(std::shared_ptr<const ViewTables> tables);

  // Fills out_rgba (width*height RGBA8, sRGB-encoded when srgb) or returns !ok
  // and leaves out_rgba untouched.
  ViewOutcome render(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool,
                     uint8_t* out_rgba, bool srgb);

 private:
  bool trace(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool, ViewOutcome* outcome);
  void interpolate(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool);
  void accumulate(bool static_view, WorkerPool& pool, uint32_t pixel_count);

  std::shared_ptr<const ViewTables> tables_;
  std::vector<int32_t> visible_of_point_;  // point index -> visible index, -1 if not visible
  std::vector<uint32_t> touched_points_;
  std::vector<float> origins_, directions_, sample_px_, ray_rgb_;
  std::vector<uint32_t> point_index_;
  std::vector<glm::vec3> point_rgb_;
  std::vector<glm::vec3> image_, history_;
  uint32_t history_frames_ = 0;
  ViewRequest last_{};
  bool has_last_ = false;
  int canvas_offset_x_ = 0, canvas_offset_y_ = 0;
};

// Linear [0,1] -> sRGB 8 bit (IEC 61966-2-1).
uint8_t encode_srgb8(float linear);

}  // namespace foveart::layer
