// The temporal measure's sums (temporal_metrics.hpp).
#include "temporal_metrics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace foveart::tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_size(const foveation::ImageRgb& image, const foveation::EccentricityMap& map, const char* what) {
  if (image.width_px != map.width_px || image.height_px != map.height_px ||
      image.rgb.size() != map.ring.size() * 3)
    throw std::invalid_argument(std::string("TemporalError::add_frame: the ") + what + " is " +
                                std::to_string(image.width_px) + "x" + std::to_string(image.height_px) +
                                ", the eccentricity map " + std::to_string(map.width_px) + "x" +
                                std::to_string(map.height_px));
}

TemporalRings finish(const std::array<double, foveation::kRingCount>& flicker_sum,
                     const std::array<std::uint64_t, foveation::kRingCount>& flicker_n,
                     const std::array<double, foveation::kRingCount>& error_sum,
                     const std::array<std::uint64_t, foveation::kRingCount>& error_n) {
  TemporalRings out;
  for (std::size_t r = 0; r < out.size(); ++r) {
    out[r].pair_values = flicker_n[r];
    out[r].frame_values = error_n[r];
    out[r].flicker_rms = flicker_n[r] ? std::sqrt(flicker_sum[r] / double(flicker_n[r])) : kNaN;
    out[r].error_mse = error_n[r] ? error_sum[r] / double(error_n[r]) : kNaN;
  }
  return out;
}

}  // namespace

void TemporalError::add_frame(const foveation::ImageRgb& image, const foveation::ImageRgb& reference,
                              const foveation::EccentricityMap& map) {
  check_size(image, map, "image");
  check_size(reference, map, "reference");
  const bool pair = frames_ > 0;
  if (pair && (previous_image_.width_px != image.width_px || previous_image_.height_px != image.height_px))
    throw std::invalid_argument("TemporalError::add_frame: frame " + std::to_string(frames_) +
                                " differs in size from the frame before");
  for (std::size_t i = 0; i < map.ring.size(); ++i) {
    const std::size_t r = map.ring[i];
    double e2 = 0.0, f2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t k = i * 3 + c;
      const double e = double(image.rgb[k]) - double(reference.rgb[k]);
      e2 += e * e;
      if (pair) {
        const double f = (double(image.rgb[k]) - double(previous_image_.rgb[k])) -
                         (double(reference.rgb[k]) - double(previous_reference_.rgb[k]));
        f2 += f * f;
      }
    }
    error_sum_[r] += e2;
    error_n_[r] += 3;
    if (pair) {
      flicker_sum_[r] += f2;
      flicker_n_[r] += 3;
    }
  }
  previous_image_ = image;
  previous_reference_ = reference;
  ++frames_;
}

TemporalRings TemporalError::rings() const { return finish(flicker_sum_, flicker_n_, error_sum_, error_n_); }

void ReferenceFloor::add_frame(const std::vector<float>& residual_mse, const foveation::EccentricityMap& map) {
  if (residual_mse.size() != map.ring.size())
    throw std::invalid_argument("ReferenceFloor::add_frame: " + std::to_string(residual_mse.size()) +
                                " residuals for a map of " + std::to_string(map.ring.size()) + " pixels");
  const bool pair = !previous_.empty();
  if (pair && previous_.size() != residual_mse.size())
    throw std::invalid_argument("ReferenceFloor::add_frame: a frame differs in size from the frame before");
  for (std::size_t i = 0; i < map.ring.size(); ++i) {
    const std::size_t r = map.ring[i];
    // Per pixel the mean over channels: counted as 3 values so that the counts match TemporalError's.
    error_sum_[r] += 3.0 * double(residual_mse[i]);
    error_n_[r] += 3;
    if (pair) {
      flicker_sum_[r] += 3.0 * (double(residual_mse[i]) + double(previous_[i]));
      flicker_n_[r] += 3;
    }
  }
  previous_ = residual_mse;
}

TemporalRings ReferenceFloor::rings() const { return finish(flicker_sum_, flicker_n_, error_sum_, error_n_); }

}  // namespace foveart::tools
