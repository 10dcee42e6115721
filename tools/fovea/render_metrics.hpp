// Image comparison for `fovea render --mode both`: PSNR and SSIM of the
// foveated image against the full one, overall and per eccentricity ring.
#pragma once

#include <foveation/image.hpp>

#include <foveation/ray_trace.h>

#include <glm/vec2.hpp>

#include <vector>

namespace foveart::tools {

struct RingMetrics {
  double from_deg = 0.0;
  double to_deg = 0.0;
  double psnr = 0.0;
  double ssim = 0.0;
  uint64_t pixels = 0;
};

struct ImageComparison {
  double psnr = 0.0;  // dB over RGB after sRGB encoding, peak 1 (inf when identical)
  double ssim = 0.0;  // mean SSIM of luma, 8x8 windows
  std::vector<RingMetrics> rings;
};

// Rings are bounded by the angle between a pixel's ray and the gaze ray.
ImageComparison compare_images(const foveation::ImageRgb& test, const foveation::ImageRgb& reference,
                               const FoveartEyeView& view, glm::vec2 gaze_px,
                               const std::vector<double>& ring_edges_deg);

}  // namespace foveart::tools
