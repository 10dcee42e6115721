// Where the layer's gaze comes from: the FoveaRT gaze provider (predicted to
// the frame's display time), the runtime's XR_EXT_eye_gaze_interaction (located
// at display time) or nothing (fixed foveation at the lens centre).
#pragma once

#include <memory>
#include <string>

#include <glm/vec3.hpp>

#include "gaze_provider/host_clock.h"
#include "renderer.hpp"

namespace foveart::layer {

struct FrameGaze {
  bool valid = false;
  glm::vec3 direction_view[2]{};  // per eye, OpenXR view space (-z forward), unit
  float age_ms = 0.0f;            // at composition (now) minus the newest measurement's host time
  bool saccade = false;           // a saccade in flight, or begun since the last frame: the temporal history restarts
  bool blink = false;             // a blink held now, or begun since the last frame: the history restarts too
  XrFoveatedGazeSourceFOVEART source = XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART;
};

// One frame's question: when, and for which views.
struct GazeQuery {
  int64_t now_ns = 0;           // steady clock: composition (xrEndFrame)
  XrTime display_time = 0;      // the frame's display time on the runtime's clock
  bool runtime_clock_is_steady = true;  // XrTime is CLOCK_MONOTONIC (false: a virtual runtime clock)
  XrSpace space = XR_NULL_HANDLE;       // the projection layer's space, where the views' poses live
  const XrCompositionLayerProjectionView* views = nullptr;
  uint32_t view_count = 0;

  // Display time on the steady clock, for gaze prediction; under a virtual
  // runtime clock, now (foveated_renderer.cpp).
  int64_t steady_display_time_ns() const { return runtime_clock_is_steady ? display_time : now_ns; }
};

class GazeSource {
 public:
  virtual ~GazeSource() = default;
  // Gaze for the frame displayed at query.display_time (the provider predicts
  // to it); its age is taken at composition.
  virtual FrameGaze at(const GazeQuery& query) = 0;
};

// Never null: when the requested source cannot be opened, a source that always
// reports "no gaze" is returned and the reason is written to *out_warning.
// provider_clock: the gaze provider's host clock (null: the steady clock; tests
// pass a virtual one).
std::unique_ptr<GazeSource> create_gaze_source(const RendererSettings& settings, const SessionState& session,
                                               std::string* out_warning,
                                               std::shared_ptr<gaze::HostClock> provider_clock = nullptr);

}  // namespace foveart::layer
