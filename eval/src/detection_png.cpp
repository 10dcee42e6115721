// The detection probability as a grey PNG (detection_png.hpp).
#include <eval/detection_png.hpp>

#include <toolkit/image_io.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace foveart::eval {

bool write_detection_png(const std::string& path, const PerceptualResult& result, std::string* error) {
  std::vector<std::uint8_t> grey(result.p_detect.size());
  for (std::size_t i = 0; i < grey.size(); ++i)
    grey[i] = std::uint8_t(std::lround(255.0 * std::clamp(double(result.p_detect[i]), 0.0, 1.0)));
  return toolkit::write_png_u8(path, result.width_px, result.height_px, 1, grey, error);
}

}  // namespace foveart::eval
