// Automatic exposure from a low-resolution pre-pass of the view: what a
// glTF viewer's auto exposure does once, so that lights in photometric units
// (candela, lux) show with a visible range instead of burning out.
#pragma once

#include <foveation/executor.hpp>
#include <foveation/image.hpp>
#include <foveation/ray_trace.h>

#include <optional>
#include <string>

namespace foveart::engine {

struct AutoExposure {
  float exposure = 1.0f;           // the linear scale to apply before the tone-mapping curve
  int prepass_width_px = 0;
  int prepass_height_px = 0;

  // The share of pixels whose luminance the exposure keeps below the curve's
  // roll-off, and where that roll-off starts (Khronos PBR Neutral's 0.76): the
  // brightest tenth of the view rolls off, the rest shows as it is.
  static constexpr double kWhitePercentile = 0.90;
  static constexpr float kTargetLuminance = 0.76f;
  // Auto exposure only darkens: a view already in display range (a scene made
  // in display-referred units, most glTF models without lights) shows as made,
  // and a dim scene stays dim.
  static constexpr float kMaxExposure = 1.0f;
};

// The exposure that maps the kWhitePercentile luminance (Rec. 709 weights) of
// `image` to kTargetLuminance, at most kMaxExposure; 1 for an image without light.
float exposure_for(const foveation::ImageRgb& image);

// Renders `view` at 1/8 of its size per axis (at least 16 px, same field of
// view, 1 centred ray per pixel) through `fn` and meters it (exposure_for).
// nullopt with *error when the callback fails.
std::optional<AutoExposure> auto_exposure(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                                          foveation::Executor& executor, std::string* error);

}  // namespace foveart::engine
