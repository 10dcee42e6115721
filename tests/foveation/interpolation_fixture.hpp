// A small synthetic point set and its tables for the table/gather/cache tests:
// jittered points on a 64 x 48 canvas, denser towards the centre like a
// foveated set, plus a regular lattice with exact ties.
#pragma once

#include <cmath>
#include <random>

#include "foveation/gaze_mapping.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"

namespace foveart::foveation::test {

inline constexpr int kScreenW = 32;
inline constexpr int kScreenH = 24;

inline PointSet foveated_points(std::uint32_t seed = 1) {
  PointSet ps;
  ps.canvas_width_px = 2 * kScreenW;
  ps.canvas_height_px = 2 * kScreenH;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  // Spacing grows from 1 px at the centre to ~4 px at the edge.
  for (float y = 0.25f; y < float(ps.canvas_height_px); ) {
    const float dy = 1.0f + 3.0f * std::abs(y - kScreenH) / kScreenH;
    for (float x = 0.25f; x < float(ps.canvas_width_px); ) {
      const float dx = 1.0f + 3.0f * std::max(std::abs(x - kScreenW) / kScreenW, std::abs(y - kScreenH) / kScreenH);
      ps.position_px.push_back({std::min(x + 0.4f * dx * u(rng), float(ps.canvas_width_px) - 0.01f), y + 0.4f * dy * u(rng)});
      ps.radius_px.push_back(0.5f * dx);
      x += dx;
    }
    y += dy;
  }
  return ps;
}

// Points on integer coordinates: every pixel centre is equidistant to 4 points.
inline PointSet lattice_points() {
  PointSet ps;
  ps.canvas_width_px = 2 * kScreenW;
  ps.canvas_height_px = 2 * kScreenH;
  // Scrambled index order so "lowest index" is not "first in raster order".
  for (int y = ps.canvas_height_px; y >= 0; --y) {
    for (int x = 0; x <= ps.canvas_width_px; ++x) {
      ps.position_px.push_back({float((x * 7) % (ps.canvas_width_px + 1)), float(y)});
      ps.radius_px.push_back(0.5f);
    }
  }
  return ps;
}

inline GazeMapping centre_mapping() { return map_gaze(kScreenW, kScreenH, {kScreenW / 2.0f, kScreenH / 2.0f}); }

}  // namespace foveart::foveation::test
