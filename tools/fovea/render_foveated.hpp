// The foveated path of `fovea render`: point set and neighbour table for the
// display, visible points at the gaze, spp ray samples per point traced through
// the engine callback, one colour per point, reconstruction to every pixel.
#pragma once

#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <glm/vec2.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

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
  // Set: the display is DisplayModel::from_fov(view size, this) whatever the
  // preset (what the layer builds for a submitted XrView); unset: the preset's.
  std::optional<double> horizontal_fov_deg;
};

struct FoveatedResult {
  engine::Image image;
  uint64_t points = 0;        // visible points traced
  double precompute_ms = 0.0; // point set + neighbour table (load or build), not in total
  double trace_ms = 0.0;      // visible points + ray samples + tracing + colour slots
  double samples_ms = 0.0;    // of which: work before the trace batches (visible-point selection
                              // and disc samples are made inside the parallel batches: ~0)
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

// Frame after frame for one view: the tables are loaded or built once, the
// per-frame buffers are reused (nothing of the size of the point set or the
// image is allocated per frame).
class FoveatedRenderer {
 public:
  FoveatedRenderer(const FoveartEyeView& view, const FoveatedRequest& request);
  ~FoveatedRenderer();
  FoveatedRenderer(const FoveatedRenderer&) = delete;
  FoveatedRenderer& operator=(const FoveatedRenderer&) = delete;

  const std::string& error() const;  // non-empty when the tables could not be made
  double precompute_ms() const;

  // One frame at `gaze_px` into *out_image (resized once); result.image stays empty.
  FoveatedResult render(engine::Tracer& tracer, glm::vec2 gaze_px, engine::Image* out_image);
  // The same through any engine callback (e.g. a no-op one, to time the bookkeeping alone).
  FoveatedResult render(FoveartTraceRaysFn fn, void* user_data, glm::vec2 gaze_px, engine::Image* out_image);

  // How many of the points a frame at `gaze_px` traces fall in each tile of a
  // tiles_x-wide grid of tile_w x tile_h screen tiles (row-major; points in the
  // margin beyond the screen count in the nearest tile). Empty on error.
  std::vector<uint32_t> points_per_tile(glm::vec2 gaze_px, uint32_t tile_w, uint32_t tile_h, uint32_t tiles_x,
                                        uint32_t tiles_y) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace foveart::tools
