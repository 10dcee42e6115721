// Stage 6 of the frame on the CPU: the history's image through the display
// transform into 8-bit (sRGB) RGBA8 rows (rgba8.hpp), the swapchain's staging
// memory (HostFrame::rgba8; none: the frame stays an image).
#pragma once

#include "foveation/frame_stages.hpp"

namespace foveart::foveation {

class HostEncode final : public EncodeStage {
 public:
  bool encode(const FrameContext& frame, FrameResources& resources, Executor& executor, std::string* error) override;
};

}  // namespace foveart::foveation
