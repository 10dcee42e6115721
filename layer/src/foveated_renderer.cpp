#include "frame_engine.hpp"
#include "renderer.hpp"

namespace foveart::layer {

FoveatedRenderer::FoveatedRenderer(std::shared_ptr<SessionState> session, RendererSettings settings)
    : session_(std::move(session)), settings_(std::move(settings)) {
  stats_.type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  stats_.gazeSource = settings_.gaze_source;
  engine_ = FrameEngine::create(session_, settings_);
}

FoveatedRenderer::~FoveatedRenderer() = default;

uint32_t FoveatedRenderer::render(XrTime display_time, const XrCompositionLayerProjection& layer,
                                  XrCompositionLayerProjectionView* out_views) {
  std::lock_guard lock(mutex_);
  if (engine_ == nullptr) {
    stats_.framesFallback += layer.viewCount;
    return 0;
  }
  return engine_->render(display_time, layer, out_views, &stats_);
}

void FoveatedRenderer::stats(XrFoveatedRendererStatsFOVEART* out_stats) const {
  std::lock_guard lock(mutex_);
  void* next = out_stats->next;
  *out_stats = stats_;
  out_stats->type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  out_stats->next = next;
}

}  // namespace foveart::layer
