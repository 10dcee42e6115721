// A temporal history that survives head motion (Karis 2014; Yang, Liu & Salvi 2020,
// "A Survey of Temporal Antialiasing Techniques", section 3): each pixel of
// the current view finds where its surface was in the previous view and
// takes the previous output there (bilinear). Without depth the surface is
// taken at infinity (rotation only: needs nothing from the engine); with the
// engine's depth it is the 3-D point P = eye + direction * depth, so parallax
// is followed too. History is rejected off-screen and where P's distance lies
// outside the previous depths of the 3x3 pixels around the reprojected one,
// widened by kDisocclusionTolerance (disocclusion; one pixel's depth is one
// jittered ray's, which at an edge flips between near and far).
#pragma once

#include <cstdint>
#include <vector>

#include "foveation/executor.hpp"
#include "foveation/shader_constants.h"
#include "foveation/image.hpp"
#include "foveation/ray_trace.h"

namespace foveart::foveation {

// Relative depth disagreement beyond which history is a different surface.
inline constexpr float kDisocclusionTolerance = static_cast<float>(FOVEART_DISOCCLUSION_TOLERANCE);

// How the previous output is read between pixel centres.
enum class HistorySampling : std::uint8_t {
  bilinear,     // the 2x2 pixels around, linearly: exact for linear content, blurs the rest
  catmull_rom,  // the 4x4 around, Catmull-Rom weights, clamped to the 2x2's min/max
                // (Karis 2014): keeps detail that bilinear resampling every frame would
                // blur away under motion, without overshoot
};

// Per-pixel depth in metres along the pixel's ray: NaN = unknown (rotation
// only), +inf = nothing hit (sky).
struct ReprojectionStats {
  std::uint64_t off_screen = 0;   // pixels whose surface was outside the previous view
  std::uint64_t disoccluded = 0;  // pixels whose previous depth disagreed
  std::uint64_t with_depth = 0;   // pixels reprojected through a finite depth
};

// Warps `history` (the previous output, seen from `history_view`, with its
// per-pixel depth `history_depth_m`, empty = unknown) into `view` (per-pixel
// depth `depth_m`, empty = unknown). `warped` gets the view's size; valid[p]
// is 1 where the history holds, 0 where it is rejected.
ReprojectionStats reproject_history(const ImageRgb& history, const std::vector<float>& history_depth_m,
                                    const FoveartEyeView& history_view, const FoveartEyeView& view,
                                    const std::vector<float>& depth_m, ImageRgb& warped,
                                    std::vector<std::uint8_t>& valid, Executor& executor,
                                    HistorySampling sampling = HistorySampling::bilinear);

}  // namespace foveart::foveation
