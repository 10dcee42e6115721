#include "frame_engine.hpp"

#include "log.hpp"

namespace foveart::layer {

std::unique_ptr<FrameEngine> FrameEngine::create(std::shared_ptr<SessionState> /*session*/,
                                                 const RendererSettings& /*settings*/) {
  log(LogLevel::Warn, "foveated renderer: frame path not available in this build; views pass through");
  return nullptr;
}

}  // namespace foveart::layer
