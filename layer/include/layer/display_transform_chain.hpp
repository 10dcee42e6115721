// The display transform of a frame: an app's chained
// XrFoveatedDisplayTransformFOVEART over the configured one. Header-only, so
// an app that renders its own full frames (hello_foveated --mode full) applies
// exactly what the layer applies to the foveated ones.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include <foveation/display_transform.hpp>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::layer {

// `chained` null: the configured transform. A field that says "use the config"
// (exposure 0, ..._USE_CONFIG_FOVEART) takes the configured value; so does an
// invalid one, and *error (else left alone) says what was wrong.
inline foveation::DisplayTransform resolve_display(const XrFoveatedDisplayTransformFOVEART* chained,
                                                   const foveation::DisplayTransform& configured,
                                                   std::string* error) {
  foveation::DisplayTransform d = configured;
  if (chained == nullptr) return d;
  if (chained->exposure != 0.0f) {
    if (std::isfinite(chained->exposure) && chained->exposure > 0.0f) d.exposure = chained->exposure;
    else *error = "XrFoveatedDisplayTransformFOVEART::exposure must be finite and > 0 (0 = config)";
  }
  switch (chained->toneMap) {
    case XR_FOVEATED_TONE_MAP_NONE_FOVEART: d.tone_map = foveation::ToneMap::none; break;
    case XR_FOVEATED_TONE_MAP_PBR_NEUTRAL_FOVEART: d.tone_map = foveation::ToneMap::pbr_neutral; break;
    case XR_FOVEATED_TONE_MAP_ACES_FOVEART: d.tone_map = foveation::ToneMap::aces; break;
    case XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART: break;
    default:
      *error = "XrFoveatedDisplayTransformFOVEART::toneMap " + std::to_string(int64_t{chained->toneMap}) +
                   " is not an XrFoveatedToneMapFOVEART";
  }
  return d;
}

}  // namespace foveart::layer
