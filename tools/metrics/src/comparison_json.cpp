// JSON of an image comparison: one writer for every fovea command.
#include <metrics/comparison_json.hpp>

#include <cmath>

namespace foveart::metrics {

nlohmann::ordered_json number_or_null_json(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json comparison_json(const ImageComparison& c) {
  nlohmann::ordered_json rings = nlohmann::ordered_json::array();
  for (const RingMetrics& r : c.rings)
    rings.push_back({{"from_deg", r.from_deg}, {"to_deg", number_or_null_json(r.to_deg)}, {"pixels", r.pixels},
                     {"psnr", number_or_null_json(r.psnr)}, {"ssim", number_or_null_json(r.ssim)},
                     {"csf_rmse", number_or_null_json(r.csf_rmse)}, {"csf_psnr", number_or_null_json(r.csf_psnr)}});
  return {{"psnr", number_or_null_json(c.psnr)}, {"ssim", number_or_null_json(c.ssim)},
          {"csf_rmse", number_or_null_json(c.csf_rmse)}, {"rings", rings}};
}

}  // namespace foveart::metrics
