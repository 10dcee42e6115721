// Where the layer's gaze comes from: the FoveaRT gaze provider (predicted to
// the frame's display time) or nothing (fixed foveation at the lens centre).
#pragma once

#include <memory>
#include <string>

#include <glm/vec3.hpp>

#include "renderer.hpp"

namespace foveart::layer {

struct FrameGaze {
  bool valid = false;
  glm::vec3 direction_view[2]{};  // per eye, OpenXR view space (-z forward), unit
  float age_ms = 0.0f;            // at composition (now) minus the newest measurement's host time
  XrFoveatedGazeSourceFOVEART source = XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART;
};

class GazeSource {
 public:
  virtual ~GazeSource() = default;
  // Gaze predicted for the frame displayed at display_time_ns; its age is taken
  // at now_ns (composition). Both steady clock.
  virtual FrameGaze at(int64_t display_time_ns, int64_t now_ns) = 0;
};

// Never null: when the requested source cannot be opened, a source that always
// reports "no gaze" is returned and the reason is written to *out_warning.
std::unique_ptr<GazeSource> create_gaze_source(const RendererSettings& settings, std::string* out_warning);

}  // namespace foveart::layer
