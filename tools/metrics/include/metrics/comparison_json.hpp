// JSON of an image comparison (eval/image_metrics.hpp), the same fields in
// every fovea command: overall psnr/ssim/csf_rmse and `rings` [{from_deg,
// to_deg (null for the open last ring), pixels, psnr, ssim, csf_rmse, csf_psnr}].
// Non-finite numbers (an identical ring's PSNR, an empty ring) are null.
#pragma once

#include <metrics/image_metrics.hpp>

#include <nlohmann/json.hpp>

namespace foveart::metrics {

nlohmann::ordered_json number_or_null_json(double v);

// {"psnr", "ssim", "csf_rmse", "rings": [...]}
nlohmann::ordered_json comparison_json(const ImageComparison& comparison);

}  // namespace foveart::metrics
