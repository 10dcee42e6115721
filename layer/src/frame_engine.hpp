// The frame path of one foveated renderer: gaze -> visible points -> engine
// callback on worker threads -> interpolation (+TAA) -> upload into a
// layer-owned swapchain per eye -> rewritten subImage.
#pragma once

#include <memory>

#include "renderer.hpp"

namespace foveart::layer {

class FrameEngine {
 public:
  virtual ~FrameEngine() = default;
  // Null when the frame path cannot run for this session (logged); the
  // renderer then forwards the app's views (counted as fallback).
  static std::unique_ptr<FrameEngine> create(std::shared_ptr<SessionState> session,
                                             const RendererSettings& settings);
  virtual uint32_t render(XrTime display_time, const XrCompositionLayerProjection& layer,
                          XrCompositionLayerProjectionView* out_views, XrFoveatedRendererStatsFOVEART* stats) = 0;
};

}  // namespace foveart::layer
