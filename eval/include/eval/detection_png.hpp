// The perceptual metric's detection probability per pixel as a picture: what the lab's
// commands write beside the images they measure (fovea-eval perceptual --out, density --out).
#pragma once

#include <eval/perceptual_metric.hpp>

#include <string>

namespace foveart::eval {

// P per pixel as an 8-bit grey PNG, black 0 .. white 1; false with *error naming the file.
[[nodiscard]] bool write_detection_png(const std::string& path, const PerceptualResult& result, std::string* error);

}  // namespace foveart::eval
