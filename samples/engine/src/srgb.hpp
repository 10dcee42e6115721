// The engine's sRGB conversions are the foveation core's (one definition for
// every image FoveaRT writes or reads).
#pragma once

#include "foveation/srgb.hpp"

namespace foveart::engine {

using foveation::encode_srgb8;
using foveation::linear_to_srgb;
using foveation::srgb_to_linear;

}  // namespace foveart::engine
