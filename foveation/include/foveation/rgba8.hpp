// A frame for a swapchain (stage 6): linear radiance -> display values
// (display_transform.hpp: exposure, tone-mapping curve) -> RGBA8 rows,
// sRGB-encoded (IEC 61966-2-1) for an sRGB format the compositor decodes,
// otherwise [0, 1] -> [0, 255] as they are; alpha 255.
#pragma once

#include <cstdint>

#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "foveation/image.hpp"

namespace foveart::foveation {

// out: image.width_px * image.height_px * 4 bytes.
void encode_rgba8(const ImageRgb& image, bool srgb, const DisplayTransform& display, std::uint8_t* out,
                  Executor& executor);

}  // namespace foveart::foveation
