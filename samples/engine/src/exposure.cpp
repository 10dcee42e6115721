#include "engine/exposure.hpp"

#include <engine/render.hpp>
#include <foveation/srgb.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace foveart::engine {

float exposure_for(const foveation::ImageRgb& image) {
  std::vector<float> luminance;
  luminance.reserve(image.pixel_count());
  for (std::size_t i = 0; i < image.pixel_count(); ++i) {
    const float* p = &image.rgb[i * 3];
    const float y = foveation::rec709_luminance(p[0], p[1], p[2]);
    if (std::isfinite(y)) luminance.push_back(std::max(y, 0.0f));
  }
  if (luminance.empty()) return 1.0f;
  const auto at = luminance.begin() + std::ptrdiff_t(double(luminance.size() - 1) * AutoExposure::kWhitePercentile);
  std::nth_element(luminance.begin(), at, luminance.end());
  const float white = *at;
  return white > AutoExposure::kTargetLuminance / AutoExposure::kMaxExposure ? AutoExposure::kTargetLuminance / white
                                                                             : AutoExposure::kMaxExposure;
}

std::optional<AutoExposure> auto_exposure(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                                          foveation::Executor& executor, std::string* error) {
  FoveartEyeView small = view;
  small.width_px = std::max(16u, view.width_px / 8);
  small.height_px = std::max(16u, view.height_px / 8);
  RenderSettings settings;
  settings.spp = 1;
  settings.jitter = false;
  foveation::ImageRgb image;
  const RenderResult r = render_full(fn, user_data, small, settings, &image, executor);
  if (r.status != FOVEART_RESULT_SUCCESS) {
    *error = "auto exposure: the pre-pass callback failed with status " + std::to_string(r.status);
    return std::nullopt;
  }
  AutoExposure a;
  a.exposure = exposure_for(image);
  a.prepass_width_px = int(small.width_px);
  a.prepass_height_px = int(small.height_px);
  return a;
}

}  // namespace foveart::engine
