// Whether foveation's density shows, by the perceptual metric: one foveated frame of a view at a
// density (the thesis's density scale, content-aware density's contrast) against a converged
// reference, its rays and its density's cost; and the density scale at which the metric's
// detection crosses one half (the thesis's user study, Table 3, measured that 50 % point).
#pragma once

#include <eval/perceptual_metric.hpp>
#include <render_view/render_options.hpp>

#include <engine/tracer.hpp>
#include <foveation/executor.hpp>
#include <foveation/image.hpp>

#include <glm/vec2.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace foveart::eval {

// What stays while the density changes.
struct DensityProbe {
  engine::Tracer* tracer = nullptr;
  FoveartEyeView view{};
  glm::vec2 gaze_px{};
  // The foveated render (method, k, pattern, rays per point and content_rays, seed, preset);
  // density_scale and content_contrast are each call's.
  render_view::RenderOptions options;
  const foveation::ImageRgb* reference = nullptr;  // linear radiance of the view, converged
  const PerceptualMetric* metric = nullptr;        // PerceptualInput::kRadiance, the view's display transform
  std::optional<std::filesystem::path> cache_dir;  // the foveated tables' cache
  foveation::LogFn log;
  foveation::Executor* executor = nullptr;
  bool keep_image = false;  // DensityDetection::image: the measured frame, to be looked at
  bool ring_multiples = false;  // DensityDetection::ring_multiples: each ring's threshold multiple (slow)
};

struct DensityDetection {
  double density_scale = 1.0;
  double content_contrast = 0.0;
  double content_rays = 0.0;  // the probe's rays per point by contrast (0: off)
  double content_rays_doubling_deg = 0.0;  // and the eccentricity over which it doubles (0: off)
  double ray_fraction = 0.0;  // primary rays of the measured frame over the full render's at the same rays per pixel
  double density_ms = 0.0;    // content-aware density's part of that frame (FrameResult::density_ms)
  double frame_ms = 0.0;      // that frame's select + trace + reconstruct
  PerceptualResult p;         // the frame against the reference
  std::vector<double> ring_multiples;  // each ring's threshold multiple, when the probe asks (0: no pixels)
  foveation::ImageRgb image;  // that frame, linear radiance (empty unless the probe keeps it)
};

// One density: frames without a history, two when content-aware (it thins, or varies the rays
// per point, from the second frame by the first's colours), the last measured. False with *error (tables, engine, metric).
[[nodiscard]] bool measure_density(const DensityProbe& probe, double density_scale, double content_contrast,
                                   DensityDetection* out, std::string* error);

// The image's detection probability: its largest P (HDR-VDP-2's P_det, Mantiuk et al. 2011): the
// most visible place decides whether a viewer who looks around notices.
inline double detection_probability(const PerceptualResult& p) { return p.p_max; }

// The density scale in [lo, hi] at which detection(scale) crosses 0.5, by bisection to `tolerance`
// (detection rises as the density falls). nullopt when it does not cross there: below 0.5 at hi or
// at or above it at lo. detection returns nullopt on an error, which ends the search (nullopt too).
std::optional<double> half_detection_scale(const std::function<std::optional<double>(double)>& detection, double lo,
                                           double hi, double tolerance);

}  // namespace foveart::eval
