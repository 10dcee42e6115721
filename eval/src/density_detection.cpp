// Detection of foveation's density by the perceptual metric (density_detection.hpp).
#include <eval/density_detection.hpp>

namespace foveart::eval {

bool measure_density(const DensityProbe& probe, double density_scale, double content_contrast, DensityDetection* out,
                     std::string* error) {
  render_view::RenderOptions o = probe.options;
  o.mode = "foveated";
  o.density_scale = density_scale;
  o.content_contrast = content_contrast;
  const auto tables = render_view::load_foveated_tables(o, probe.view, probe.cache_dir, *probe.executor, probe.log, error);
  if (!tables) return false;
  foveation::ViewSettings settings = render_view::foveated_view_settings(o);
  settings.content_density.exposure = probe.metric->display().transform.exposure;
  foveation::FoveatedView view(tables, settings);
  const int frames = settings.content_density.enabled() ? 2 : 1;
  foveation::FrameResult fr;
  for (int frame = 0; frame < frames; ++frame) {
    foveation::FrameRequest request;
    request.view = probe.view;
    request.gaze_px = probe.gaze_px;
    request.frame_index = std::uint64_t(frame);
    fr = view.render(request, &foveart_engine_trace_rays, probe.tracer, *probe.executor);
    if (!fr.ok()) return *error = "foveated frame: " + fr.message, false;
  }
  *out = DensityDetection{};
  out->density_scale = density_scale;
  out->content_contrast = content_contrast;
  out->content_rays = render_view::content_rays_of(o);
  out->content_rays_doubling_deg = render_view::content_rays_doubling_of(o);
  const double full_rays = double(probe.view.width_px) * double(probe.view.height_px) * double(o.rays_per_point);
  out->ray_fraction = double(fr.rays) / full_rays;
  out->density_ms = fr.density_ms;
  out->frame_ms = fr.select_ms + fr.trace_ms + fr.reconstruct_ms;
  if (probe.keep_image) out->image = view.image();
  if (!probe.metric->evaluate(view.image(), *probe.reference, probe.gaze_px, probe.executor, out->p, *error))
    return false;
  double image_multiple = 0.0;
  return !probe.ring_multiples ||
         probe.metric->threshold_multiple(view.image(), *probe.reference, probe.gaze_px, probe.executor, image_multiple,
                                          *error, &out->ring_multiples);
}

std::optional<double> half_detection_scale(const std::function<std::optional<double>(double)>& detection, double lo,
                                           double hi, double tolerance) {
  const std::optional<double> at_lo = detection(lo), at_hi = detection(hi);
  if (!at_lo || !at_hi || *at_lo >= 0.5 || *at_hi < 0.5) return std::nullopt;
  while (hi - lo > tolerance) {
    const double mid = 0.5 * (lo + hi);
    const std::optional<double> p = detection(mid);
    if (!p) return std::nullopt;
    (*p < 0.5 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace foveart::eval
