// The foveated path of `fovea render`: point set and neighbour table for the
// display, visible points at the gaze, spp ray samples per point traced through
// the engine callback, one colour per point, reconstruction to every pixel.
#pragma once

#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <glm/vec2.hpp>

#include <optional>
#include <string>

namespace foveart::tools {

struct FoveatedRequest {
  std::string preset = "fove";
  double scale = 1.0;
  std::string method = "nn";
  int k = 1;
  int spp = 1;
  int threads = 0;
  uint64_t seed = 1;
  std::string cache_dir;
  glm::vec2 gaze_px{0.0f};
};

struct FoveatedResult {
  engine::Image image;
  uint64_t points = 0;        // visible points traced
  double precompute_ms = 0.0; // point set + neighbour table (load or build), not in total
  double trace_ms = 0.0;      // visible points + ray samples + tracing
  double samples_ms = 0.0;    // of which: visible points + ray samples (bookkeeping)
  double reconstruct_ms = 0.0;
  std::string error;          // non-empty on failure
};

// True when this build has the foveation core (foveated and both modes).
bool foveated_available();

// Per-eye size and symmetric frustum of a display preset (foveation's
// display_preset; without the core only "fove" is known). nullopt if unknown.
struct PresetGeometry {
  int width_px = 0;
  int height_px = 0;
  double half_fov_x_rad = 0.0;
  double half_fov_y_rad = 0.0;
};
std::optional<PresetGeometry> preset_geometry(const std::string& preset);

FoveatedResult render_foveated(engine::Tracer& tracer, const FoveartEyeView& view, const FoveatedRequest& request);

}  // namespace foveart::tools
