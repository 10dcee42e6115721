// One frame of reconstruction: every screen pixel is a k-tap weighted gather of
// point colours through the canvas tables (thesis 4.3; screen pixel p reads
// canvas pixel p + mapping offset).
//
// Invalid points never spread (docs/interpolation.md): a point is invalid when
// it was not sampled this frame or any channel is NaN/Inf. Its colour is stored
// as 0 with validity 0, and a pixel with an invalid tap
//   1. renormalises over its valid taps when their weight is large enough
//      (NN/MSM: any positive weight; RBF: at least half of the weight sum),
//   2. otherwise takes the nearest valid point among all NeighborTable entries,
//   3. otherwise (no valid point at all) GatherOptions::fallback_rgb.
// RBF results are clamped by default to the range of the valid point colours
// their gather block reads (RbfClamp::block: no ringing beyond the local data;
// the weights alone overshoot a step by up to ~0.6). A pixel with an invalid
// tap is clamped to its own valid taps' range (a subset of the block's).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "foveation/executor.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/image.hpp"
#include "foveation/interpolation_table.hpp"
#include "foveation/neighbor_table.hpp"

namespace foveart::foveation {

struct alignas(16) Rgba {
  float r = 0.0f;
  float g = 0.0f;
  float b = 0.0f;
  float a = 0.0f;  // 1 valid, 0 invalid
};

// Colours of every point of the point set for one frame.
struct PointColors {
  std::vector<Rgba> rgba;
  std::size_t invalid = 0;  // points marked invalid
  std::size_t size() const { return rgba.size(); }
};

// Rule 2 above: the nearest of canvas pixel `pixel`'s NeighborTable entries with a valid colour,
// in the table's order; kNoValidPoint when none is in reach. Also a pixel's depth (ImageHistory)
// and its rays (`fovea render`'s rays map).
inline constexpr std::uint32_t kNoValidPoint = UINT32_MAX;
inline std::uint32_t nearest_valid_point(const NeighborTable& nt, std::size_t pixel, const Rgba* colors) {
  for (int j = 0; j < nt.k(); ++j) {
    const std::uint32_t point = nt.neighbor(pixel, j);
    if (colors[point].a != 0.0f) return point;
  }
  return kNoValidPoint;
}

// From colours of some points (rgb: 3 floats per listed point, e.g. the
// VisiblePoints order); unlisted points are invalid. Throws std::invalid_argument
// when sizes disagree or an index is >= point_count.
PointColors point_colors_from_list(std::size_t point_count, std::span<const std::uint32_t> point_index,
                                   std::span<const float> rgb);
// From colours of all points (3 floats each) and an optional validity mask
// (0 = invalid). Throws std::invalid_argument when sizes disagree.
PointColors point_colors_from_all(std::span<const float> rgb, std::span<const std::uint8_t> valid = {});

// De-ringing of RBF results (MSM and NN never leave their taps' range).
enum class RbfClamp : std::uint8_t {
  off,    // the thesis's plain RBF: overshoots a 0/1 step by up to ~0.6
  taps,   // each pixel within its own valid taps' min/max (O(k) per pixel)
  block,  // each pixel within the min/max of the valid points its gather block
          // reads (<= 8x8 pixels, the union of their taps; O(1) per pixel)
};

// "off" | "taps" | "block", as fovea reconstruct --rbf-clamp spells them.
std::string_view rbf_clamp_name(RbfClamp clamp);
std::optional<RbfClamp> parse_rbf_clamp(std::string_view name);

struct GatherOptions {
  RbfClamp rbf_clamp = RbfClamp::block;
  std::array<float, 3> fallback_rgb{};  // no valid point in reach
  bool simd = true;                    // AVX2/FMA/F16C kernel when the CPU has them (false: portable code)
};

// Counts of pixels that took the invalid-point paths (0 when every tap was valid).
struct GatherStats {
  std::uint64_t renormalized = 0;
  std::uint64_t nearest_valid = 0;
  std::uint64_t fallback = 0;
};

// Reconstructs the screen image `out` (resized to the mapping's screen). Throws
// std::invalid_argument when the tables disagree or the screen does not fit the
// canvas at the mapping's offset. colors.size() must cover every point index.
GatherStats gather(const NeighborTable& neighbors, const InterpolationTable& table, const PointColors& colors,
                   const GazeMapping& mapping, ImageRgb& out, Executor& executor, const GatherOptions& options = {});

}  // namespace foveart::foveation
