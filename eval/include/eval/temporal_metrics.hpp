// The temporal measure of a rendered sequence against a converged reference
// sequence, per eccentricity ring (docs/pricelist.md "Temporal columns").
// Pure arithmetic on display values; frames are added one at a time so that a
// sequence never has to be held in memory.
//
// With I_t the image and R_t the reference of frame t (display values) and the
// rings of frame t (the gaze moves, so the rings move with it):
//
//   flicker_rms = sqrt( sum over pairs t >= 1, pixels of the ring, channels of
//                       ((I_t - I_{t-1}) - (R_t - R_{t-1}))^2  /  count )
//     the frame-to-frame change beyond the truth's own change (motion changes
//     R too; an image that follows the truth exactly has 0);
//   error_mse   = sum over frames, pixels of the ring, channels of (I_t - R_t)^2 / count
//     (ghosting, lag and noise alike), and its PSNR 10 log10(1 / error_mse);
//   flicker_tracked_rms: the same change of the error e_t = I_t - R_t along the
//     motion, e_t - W(e_{t-1}), with W(e_{t-1}) the previous error warped into
//     frame t (each pixel's surface where it was a frame before), over the
//     pixels whose surface was in view: what an eye that holds the world still
//     on its retina (the vestibulo-ocular reflex while the head turns) sees
//     change. An error that moves with the content (a blurred edge, a constant
//     offset) is not tracked flicker; one fixed on the screen while the content
//     moves under it (sparse samples, a fixed jitter) is;
//   flicker_csf_rms: the fixed-pixel change e_t - e_{t-1} weighted by what the
//     eye resolves where each pixel lies (eval/csf_error.hpp: the luma
//     change split into octave bands, each weighted by the foveated contrast
//     sensitivity at the pixel's eccentricity), RMS over the ring's pixels:
//     the part of the flicker the eye can see. Where the eye resolves every
//     band (the gaze point) it is the luma change itself; in the periphery the
//     fine bands fade. Only with a map that has eccentricities (NaN otherwise).
//
// Every frame's sums are kept, so that the same measure can be pooled over any
// rings and any frames (pooled()): frame by frame (by_frame) to show where in a
// sequence the flicker comes from, or over the frames whose TAA history has
// settled (settled_frames).
//
// The reference's own noise adds to both (ReferenceFloor): with e_t its error
// against the truth, independent between frames, E[flicker^2] = true^2 +
// E[(e_t - e_{t-1})^2] and E[error_mse] = true + E[e_t^2].
#pragma once

#include <foveation/image.hpp>
#include <metrics/image_metrics.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace foveart::eval {

struct TemporalRing {
  std::uint64_t frame_values = 0;  // pixel-channel values summed into error_mse
  std::uint64_t pair_values = 0;   // pixel-channel values summed into flicker_rms
  std::uint64_t tracked_pair_values = 0;  // ... into flicker_tracked_rms
  double flicker_rms = 0.0;        // NaN without a pair (fewer than 2 frames, or an empty ring)
  double flicker_tracked_rms = 0.0;  // NaN without a tracked pair
  std::uint64_t csf_pair_pixels = 0;  // pixels summed into flicker_csf_rms
  double flicker_csf_rms = 0.0;       // NaN without a pair or without the map's eccentricities
  double error_mse = 0.0;          // NaN for an empty ring
  double psnr_db() const { return metrics::psnr_of_mse(error_mse); }
};

using TemporalRings = std::array<TemporalRing, metrics::kRingCount>;

// Rings [begin, end) of metrics::kRingEdgesDeg pooled into one region.
struct RingBand {
  const char* name;
  std::size_t begin;
  std::size_t end;
};
// The two regions of the temporal goal: where the user looks
// (0-5 deg: no ghosting) and the periphery (> 20 deg: flicker).
inline constexpr RingBand kCentralBand{"centre", 0, 2};
inline constexpr RingBand kPeripheralBand{"periphery", 4, metrics::kRingCount};

// Per frame: 1 where a TAA history has run at least `settle_frames` frames since
// it last restarted — restart[t] != 0 marks a frame that restarts it (the first,
// a saccade's or a blink's frames) — so that pooling over them measures a
// settled TAA, without its cold start and the frames after a saccade. Frame 0
// always counts as a restart.
std::vector<std::uint8_t> settled_frames(const std::vector<std::uint8_t>& restart, int settle_frames);

// The previous frame's error warped into this frame (taa_reprojection.hpp's
// reproject_history of previous_error()): valid[p] == 0 where the surface was
// not in the previous view.
struct TrackedPrevious {
  const foveation::ImageRgb* warped_error = nullptr;
  const std::vector<std::uint8_t>* valid = nullptr;
};

class TemporalError {
 public:
  // Frame t: image and reference in display values, both of map's size; map
  // holds frame t's rings; `tracked` (optional, from frame 1 on) the previous
  // error along the motion. Throws std::invalid_argument on mismatched sizes.
  void add_frame(const foveation::ImageRgb& image, const foveation::ImageRgb& reference,
                 const metrics::EccentricityMap& map, const TrackedPrevious* tracked = nullptr);
  TemporalRings rings() const;
  // Rings [band.begin, band.end) pooled over the frames t with frame_mask[t] != 0
  // (all frames when frame_mask is null): error over those frames, flicker over
  // their pairs (t-1, t). Throws std::invalid_argument on a bad band or mask size.
  TemporalRing pooled(const RingBand& band, const std::vector<std::uint8_t>* frame_mask = nullptr) const;
  // pooled(band) of each frame alone (frame 0 has no flicker: NaN).
  std::vector<TemporalRing> by_frame(const RingBand& band) const;
  int frames() const { return frames_; }
  // e_{t-1} = I_{t-1} - R_{t-1} of the last frame added (empty before the first).
  const foveation::ImageRgb& previous_error() const { return previous_error_; }

 private:
  // One frame's sums per ring: its error, and its pair with the frame before.
  struct FrameSums {
    std::array<double, metrics::kRingCount> flicker{}, tracked{}, error{}, csf{};
    std::array<std::uint64_t, metrics::kRingCount> flicker_n{}, tracked_n{}, error_n{}, csf_n{};
  };
  foveation::ImageRgb previous_error_, error_;
  std::vector<FrameSums> sums_;
  int frames_ = 0;
};

// The reference sequence's own contribution: per pixel of frame t, the
// reference's estimated squared error against the truth (Reference's
// half_difference2 / 4, the mean over channels). flicker_rms is the RMS of
// e_t - e_{t-1} (variances add: r_t + r_{t-1}), error_mse the mean of r_t;
// flicker_tracked_rms is given the same value, a bound: warped, e_{t-1} is a
// bilinear mix of neighbouring pixels' errors, of at most their variance.
// flicker_csf_rms comes from the signed luma half difference d_t (Reference's
// half_difference_luma; r_t is estimated by d_t / 2) when every frame gives it:
// the CSF weighting W_t of frame t is linear, so the reference adds
// E[W_t(r_t)^2] + E[W_t(r_{t-1})^2] to the squared weighted flicker. The plain
// floor does not bound it: the weighting lowers a track's flicker more than
// the reference's noise when that noise is coarser than the track's.
class ReferenceFloor {
 public:
  // Throws std::invalid_argument when residual_mse, half_difference_luma (optional) and map differ in size.
  void add_frame(const std::vector<float>& residual_mse, const metrics::EccentricityMap& map,
                 const std::vector<float>* half_difference_luma = nullptr);
  TemporalRings rings() const;

 private:
  std::vector<float> previous_, previous_luma_;
  bool luma_every_frame_ = true;
  std::array<double, metrics::kRingCount> flicker_sum_{}, error_sum_{}, csf_sum_{};
  std::array<std::uint64_t, metrics::kRingCount> flicker_n_{}, error_n_{}, csf_n_{};
};

// *out = image blurred by the binomial kernel [1 2 1]/4 along rows, then
// columns (edge pixels repeated): a fixed spatial filter, so a sequence of
// blurred truths is soft but stable in the world.
void binomial_blur_3x3(const foveation::ImageRgb& image, foveation::ImageRgb* out);

}  // namespace foveart::eval
