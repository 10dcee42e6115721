// The full render with a foveated view's temporal history (full_taa.hpp).
#include <eval/full_taa.hpp>

#include <engine/render.hpp>

#include <chrono>
#include <stdexcept>

namespace foveart::eval {

// The blend options of make_temporal_history (foveated_view.cpp): per ray, for frames of rays_per_point rays.
FullTaaRender::FullTaaRender(const foveation::ViewSettings& settings)
    : settings_(settings), taa_(settings.blend_options()) {
  // An image history only: a render cache keeps rays, not images, and TAA off keeps nothing.
  if (settings.temporal != foveation::TemporalMode::image)
    throw std::invalid_argument("full render with TAA: the settings must have an image history");
  if (settings.rays_per_point < 1) throw std::invalid_argument("full render with TAA: rays per pixel must be >= 1");
}

std::uint64_t FullTaaRender::frame_seed(std::uint64_t frame_index) const {
  return settings_.frame_sample_seed(frame_index);
}

FullTaaFrame FullTaaRender::render(FoveartTraceRaysFn trace_rays, void* user_data, const FoveartEyeView& view,
                                   glm::vec2 gaze_px, std::uint64_t frame_index, foveation::Executor& executor) {
  engine::RenderSettings rs;
  rs.spp = settings_.rays_per_point;
  rs.seed = frame_seed(frame_index);
  rs.pixel_filter = settings_.pixel_filter;
  const engine::RenderResult rr = engine::render_full(trace_rays, user_data, view, rs, &frame_, executor);
  FullTaaFrame f;
  f.status = rr.status;
  f.trace_ms = rr.trace_ms;
  if (rr.status != FOVEART_RESULT_SUCCESS) return f;
  const auto t0 = std::chrono::steady_clock::now();
  taa_.accumulate(frame_, gaze_px, executor);
  f.temporal_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

}  // namespace foveart::eval
