#include "foveation/frame_stages.hpp"

#include "foveation/host_encode.hpp"
#include "foveation/rgba8.hpp"

namespace foveart::foveation {

HostFrame* host_frame(FrameResources& resources, const char* stage, std::string* error) {
  HostFrame* host = resources.host();
  if (host == nullptr) *error = std::string(stage) + " runs on the host, and this frame's resources are the device's";
  return host;
}

bool HostEncode::encode(const FrameContext& frame, FrameResources& resources, Executor& executor,
                        std::string* error) {
  HostFrame* host = host_frame(resources, "the CPU's encode", error);
  if (host == nullptr) return false;
  if (host->rgba8 == nullptr) return true;
  const ImageRgb& image = host->output != nullptr ? *host->output : host->reconstructed;
  if (image.width_px != int(frame.view.width_px) || image.height_px != int(frame.view.height_px)) {
    *error = "the CPU's encode: no image of this frame's view size to encode";
    return false;
  }
  encode_rgba8(image, host->srgb, host->display, host->rgba8, executor);
  return true;
}

}  // namespace foveart::foveation
