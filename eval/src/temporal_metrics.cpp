// The temporal measure's sums (temporal_metrics.hpp).
#include <eval/temporal_metrics.hpp>

#include <metrics/csf_error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace foveart::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_size(const foveation::ImageRgb& image, const metrics::EccentricityMap& map, const char* what) {
  if (image.width_px != map.width_px || image.height_px != map.height_px ||
      image.rgb.size() != map.ring.size() * 3)
    throw std::invalid_argument(std::string("TemporalError::add_frame: the ") + what + " is " +
                                std::to_string(image.width_px) + "x" + std::to_string(image.height_px) +
                                ", the eccentricity map " + std::to_string(map.width_px) + "x" +
                                std::to_string(map.height_px));
}

TemporalRings finish(const std::array<double, metrics::kRingCount>& flicker_sum,
                     const std::array<std::uint64_t, metrics::kRingCount>& flicker_n,
                     const std::array<double, metrics::kRingCount>& error_sum,
                     const std::array<std::uint64_t, metrics::kRingCount>& error_n) {
  TemporalRings out;
  for (std::size_t r = 0; r < out.size(); ++r) {
    out[r].pair_values = flicker_n[r];
    out[r].frame_values = error_n[r];
    out[r].flicker_rms = flicker_n[r] ? std::sqrt(flicker_sum[r] / double(flicker_n[r])) : kNaN;
    out[r].error_mse = error_n[r] ? error_sum[r] / double(error_n[r]) : kNaN;
  }
  return out;
}

bool map_has_eccentricity(const metrics::EccentricityMap& map) {
  return map.eccentricity_deg.size() == map.ring.size() && map.pixels_per_deg.size() == map.ring.size();
}

}  // namespace

void TemporalError::add_frame(const foveation::ImageRgb& image, const foveation::ImageRgb& reference,
                              const metrics::EccentricityMap& map, const TrackedPrevious* tracked) {
  check_size(image, map, "image");
  check_size(reference, map, "reference");
  const bool pair = frames_ > 0;
  if (pair && (previous_error_.width_px != image.width_px || previous_error_.height_px != image.height_px))
    throw std::invalid_argument("TemporalError::add_frame: frame " + std::to_string(frames_) +
                                " differs in size from the frame before");
  const bool track = pair && tracked != nullptr && tracked->warped_error != nullptr && tracked->valid != nullptr;
  if (track) {
    check_size(*tracked->warped_error, map, "warped previous error");
    if (tracked->valid->size() != map.ring.size())
      throw std::invalid_argument("TemporalError::add_frame: the tracked validity has " +
                                  std::to_string(tracked->valid->size()) + " entries for a map of " +
                                  std::to_string(map.ring.size()) + " pixels");
  }
  error_.width_px = image.width_px;
  error_.height_px = image.height_px;
  error_.rgb.resize(image.rgb.size());
  FrameSums& sums = sums_.emplace_back();
  for (std::size_t i = 0; i < map.ring.size(); ++i) {
    const std::size_t r = map.ring[i];
    const bool tracked_here = track && (*tracked->valid)[i] != 0;
    double e2 = 0.0, f2 = 0.0, g2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t k = i * 3 + c;
      const double e = double(image.rgb[k]) - double(reference.rgb[k]);
      error_.rgb[k] = float(e);
      e2 += e * e;
      if (pair) {
        // (I_t - I_{t-1}) - (R_t - R_{t-1}) = e_t - e_{t-1}
        const double f = e - double(previous_error_.rgb[k]);
        f2 += f * f;
      }
      if (tracked_here) {
        const double g = e - double(tracked->warped_error->rgb[k]);
        g2 += g * g;
      }
    }
    sums.error[r] += e2;
    sums.error_n[r] += 3;
    if (pair) {
      sums.flicker[r] += f2;
      sums.flicker_n[r] += 3;
    }
    if (tracked_here) {
      sums.tracked[r] += g2;
      sums.tracked_n[r] += 3;
    }
  }
  if (pair && map_has_eccentricity(map)) {
    // e_t - e_{t-1} weighted by what the eye resolves where the pixel lies (csf_error.hpp), luma only.
    const std::vector<float> csf = metrics::csf_error_map(previous_error_, error_, map);
    for (std::size_t i = 0; i < map.ring.size(); ++i) {
      sums.csf[map.ring[i]] += double(csf[i]) * double(csf[i]);
      sums.csf_n[map.ring[i]] += 1;
    }
  }
  std::swap(previous_error_, error_);
  ++frames_;
}

TemporalRing TemporalError::pooled(const RingBand& band, const std::vector<std::uint8_t>* frame_mask) const {
  if (band.begin >= band.end || band.end > metrics::kRingCount)
    throw std::invalid_argument("TemporalError::pooled: rings [" + std::to_string(band.begin) + ", " +
                                std::to_string(band.end) + ") of " + std::to_string(metrics::kRingCount));
  if (frame_mask != nullptr && frame_mask->size() != sums_.size())
    throw std::invalid_argument("TemporalError::pooled: a mask of " + std::to_string(frame_mask->size()) +
                                " frames for " + std::to_string(sums_.size()));
  double flicker = 0.0, tracked = 0.0, error = 0.0, csf = 0.0;
  TemporalRing out;
  for (std::size_t t = 0; t < sums_.size(); ++t) {
    if (frame_mask != nullptr && (*frame_mask)[t] == 0) continue;
    for (std::size_t r = band.begin; r < band.end; ++r) {
      flicker += sums_[t].flicker[r];
      tracked += sums_[t].tracked[r];
      error += sums_[t].error[r];
      csf += sums_[t].csf[r];
      out.csf_pair_pixels += sums_[t].csf_n[r];
      out.pair_values += sums_[t].flicker_n[r];
      out.tracked_pair_values += sums_[t].tracked_n[r];
      out.frame_values += sums_[t].error_n[r];
    }
  }
  out.flicker_rms = out.pair_values ? std::sqrt(flicker / double(out.pair_values)) : kNaN;
  out.flicker_tracked_rms = out.tracked_pair_values ? std::sqrt(tracked / double(out.tracked_pair_values)) : kNaN;
  out.error_mse = out.frame_values ? error / double(out.frame_values) : kNaN;
  out.flicker_csf_rms = out.csf_pair_pixels ? std::sqrt(csf / double(out.csf_pair_pixels)) : kNaN;
  return out;
}

TemporalRings TemporalError::rings() const {
  TemporalRings out;
  for (std::size_t r = 0; r < out.size(); ++r) out[r] = pooled(RingBand{"ring", r, r + 1});
  return out;
}

std::vector<TemporalRing> TemporalError::by_frame(const RingBand& band) const {
  std::vector<TemporalRing> out;
  std::vector<std::uint8_t> one(sums_.size(), 0);
  for (std::size_t t = 0; t < sums_.size(); ++t) {
    one[t] = 1;
    out.push_back(pooled(band, &one));
    one[t] = 0;
  }
  return out;
}

std::vector<std::uint8_t> settled_frames(const std::vector<std::uint8_t>& restart, int settle_frames) {
  std::vector<std::uint8_t> settled(restart.size(), 0);
  std::size_t last_restart = 0;
  for (std::size_t t = 0; t < restart.size(); ++t) {
    if (t == 0 || restart[t] != 0) last_restart = t;
    settled[t] = t - last_restart >= std::size_t(std::max(settle_frames, 0)) && t != last_restart ? 1 : 0;
  }
  return settled;
}

void ReferenceFloor::add_frame(const std::vector<float>& residual_mse, const metrics::EccentricityMap& map,
                               const std::vector<float>* half_difference_luma) {
  if (residual_mse.size() != map.ring.size())
    throw std::invalid_argument("ReferenceFloor::add_frame: " + std::to_string(residual_mse.size()) +
                                " residuals for a map of " + std::to_string(map.ring.size()) + " pixels");
  if (half_difference_luma != nullptr && half_difference_luma->size() != map.ring.size())
    throw std::invalid_argument("ReferenceFloor::add_frame: " + std::to_string(half_difference_luma->size()) +
                                " luma differences for a map of " + std::to_string(map.ring.size()) + " pixels");
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
  luma_every_frame_ = luma_every_frame_ && half_difference_luma != nullptr && map_has_eccentricity(map);
  if (!luma_every_frame_) {
    previous_luma_.clear();
  } else {
    if (pair) {
      // W_t(r_t) and W_t(r_{t-1}), the luma of r estimated by d / 2.
      const auto weighted = [&](const std::vector<float>& d) {
        std::vector<double> r(d.size());
        for (std::size_t i = 0; i < d.size(); ++i) r[i] = 0.5 * double(d[i]);
        return metrics::csf_weighted_luma(r, map);
      };
      const std::vector<float> now = weighted(*half_difference_luma), before = weighted(previous_luma_);
      for (std::size_t i = 0; i < map.ring.size(); ++i) {
        csf_sum_[map.ring[i]] += double(now[i]) * double(now[i]) + double(before[i]) * double(before[i]);
        csf_n_[map.ring[i]] += 1;
      }
    }
    previous_luma_ = *half_difference_luma;
  }
  previous_ = residual_mse;
}

TemporalRings ReferenceFloor::rings() const {
  TemporalRings out = finish(flicker_sum_, flicker_n_, error_sum_, error_n_);
  // Along the motion e_{t-1} is a bilinear mix of neighbouring residuals (weights w with sum w^2 <= 1):
  // its variance is at most theirs, so the fixed-pixel floor bounds the tracked one.
  for (TemporalRing& r : out) r.flicker_tracked_rms = r.flicker_rms, r.tracked_pair_values = r.pair_values;
  for (std::size_t r = 0; r < out.size(); ++r) {
    out[r].csf_pair_pixels = luma_every_frame_ ? csf_n_[r] : 0;
    out[r].flicker_csf_rms = out[r].csf_pair_pixels ? std::sqrt(csf_sum_[r] / double(csf_n_[r])) : kNaN;
  }
  return out;
}

void binomial_blur_3x3(const foveation::ImageRgb& image, foveation::ImageRgb* out) {
  const int w = image.width_px, h = image.height_px;
  foveation::ImageRgb rows(w, h);
  *out = foveation::ImageRgb(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float* l = image.at(std::max(x - 1, 0), y);
      const float* m = image.at(x, y);
      const float* r = image.at(std::min(x + 1, w - 1), y);
      for (int c = 0; c < 3; ++c) rows.at(x, y)[c] = 0.25f * l[c] + 0.5f * m[c] + 0.25f * r[c];
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float* u = rows.at(x, std::max(y - 1, 0));
      const float* m = rows.at(x, y);
      const float* d = rows.at(x, std::min(y + 1, h - 1));
      for (int c = 0; c < 3; ++c) out->at(x, y)[c] = 0.25f * u[c] + 0.5f * m[c] + 0.25f * d[c];
    }
  }
}

}  // namespace foveart::eval
