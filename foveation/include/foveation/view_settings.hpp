// What one view's foveated frames are asked to do: the settings chosen once
// (temporal_view_settings() fills them for each temporal mode) and the request
// of each frame.
#pragma once

#include <cstdint>

#include <glm/vec2.hpp>

#include "foveation/content_density.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/ray_trace.h"
#include "foveation/gather.hpp"
#include "foveation/temporal_blend.hpp"
#include "foveation/temporal_mode.hpp"

namespace foveart::foveation {

struct ViewSettings {
  int rays_per_point = 1;            // jittered rays in each point's disc, averaged (thesis 4.2)
  std::uint64_t sample_seed = 1;     // where in its disc each ray goes
  PixelFilter pixel_filter = PixelFilter::box;  // how a pixel-grid point's rays spread (ray_samples.hpp)
  bool new_jitter_each_frame = false;  // sample_seed + frame_index: the history then converges over frames
  // What a frame keeps from earlier frames (thesis 2.5, 6.1; temporal_mode.hpp).
  TemporalMode temporal = TemporalMode::off;
  TemporalOptions temporal_options;  // for 1 ray per point; more rays blend with temporal_options_for_rays
  // TemporalMode::rays: a kept ray is forgotten this many frames after it was
  // traced (bounds the rays kept on a still view; 0: never), and all of them at
  // the history's restarts (a saccade's or a blink's onset, a gaze jump).
  std::uint32_t ray_cache_max_age_frames = 32;
  RbfClamp rbf_clamp = RbfClamp::block;
  // Density that follows the content (content_density.hpp): off by default. Applies
  // with the temporal modes off and image; the render cache keeps every point's rays.
  ContentDensityOptions content_density;
  // The foveation centre stays put while the gaze stays within this many
  // degrees of it (fixation: microsaccades, drift, tracker noise), and jumps
  // to the gaze at once beyond it or on a saccade or blink (docs/foveation.md).
  // 0: the centre follows every whole-pixel gaze change.
  double centre_deadband_deg = 1.0;
  // false: render() stops after the trace and the history's decision; the
  // caller reconstructs from hand_off() (the layer's GPU path).
  bool reconstruct_on_cpu = true;

  // The jitter seed of frame `frame_index`.
  std::uint64_t frame_sample_seed(std::uint64_t frame_index) const {
    return sample_seed + (new_jitter_each_frame ? frame_index : 0);
  }
  // The history's blend for frames of rays_per_point rays (temporal_options_for_rays).
  TemporalOptions blend_options() const { return temporal_options_for_rays(temporal_options, rays_per_point); }
};

// The view settings of a temporal mode at rays_per_point jittered rays per
// point: the history, the per-frame jitter and the pixel filter it fixes.
ViewSettings temporal_view_settings(TemporalMode mode, int rays_per_point, std::uint64_t sample_seed);

struct FrameRequest {
  FoveartEyeView view{};       // pose, frustum and size; the size must be the tables' display
  glm::vec2 gaze_px{};         // the gaze in this view's pixels (rounded to whole pixels); the centre follows it
  std::uint64_t frame_index = 0;
  bool saccade = false;        // the gaze provider saw a saccade: the history restarts
  bool blink = false;          // the eye is closed (the provider holds its last gaze): the history restarts
};

}  // namespace foveart::foveation
